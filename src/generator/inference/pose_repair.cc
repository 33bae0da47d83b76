#include "generator/inference/pose_repair.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>

#include "constraints/torch/angle_penalty.h"

namespace motionfork {

struct PoseRepair::Impl {
  PoseRepairOptions options;
  AnglePenalty original{nullptr};  // the ranges as given: which poses break one
  AnglePenalty narrowed{nullptr};  // the ranges narrowed by the margin: the repair's target
  std::vector<std::set<int>> constraint_joints;  // joints each constraint reads
  std::vector<std::set<int>> part_joints;
  torch::Tensor bone_child, bone_parent;  // [J - 1] int64
  int num_joints = 0;
  std::vector<std::vector<int>> rigid;    // joints of each rigid group (not the root)
  std::vector<std::vector<int>> subtree;  // per joint: itself and its descendants
};

namespace {

// Joints a register (bone or cross product of registers) reads.
void RegisterJoints(const ConstraintSet& set, int r, std::set<int>* out) {
  const VectorOp& op = set.ops().at(r);
  if (op.kind == VectorOp::Kind::kBone) {
    out->insert(op.x);
    out->insert(op.y);
  } else {
    RegisterJoints(set, op.x, out);
    RegisterJoints(set, op.y, out);
  }
}

ConstraintSetSpec Narrowed(ConstraintSetSpec spec, double margin) {
  for (ConstraintSpec& c : spec.constraints) {
    double lo = c.lower_deg > 0 ? c.lower_deg + margin : c.lower_deg;
    double hi = c.upper_deg < 180 ? c.upper_deg - margin : c.upper_deg;
    if (lo > hi) lo = hi = 0.5 * (c.lower_deg + c.upper_deg);
    c.lower_deg = lo;
    c.upper_deg = hi;
  }
  return spec;
}

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Rotation taking direction a to direction b (the shortest turn).
Matrix3d Align(const Vector3d& a, const Vector3d& b) {
  if (a.norm() < 1e-12 || b.norm() < 1e-12) return Matrix3d::Identity();
  return Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix();
}

// Least-squares rotation R minimising sum |R u_i - v_i|^2 (Kabsch). Fewer than two usable pairs:
// the shortest turn of the one direction.
Matrix3d FitRotation(const std::vector<Vector3d>& u, const std::vector<Vector3d>& v) {
  if (u.size() == 1) return Align(u[0], v[0]);
  Matrix3d h = Matrix3d::Zero();
  for (size_t i = 0; i < u.size(); ++i) h += u[i] * v[i].transpose();
  Eigen::JacobiSVD<Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix3d d = Matrix3d::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  return svd.matrixV() * d * svd.matrixU().transpose();
}

// R0 takes u_d onto v_d's direction; then the turn about that axis that best fits the pairs.
Matrix3d FitTwist(const Vector3d& ud, const Vector3d& vd, const std::vector<Vector3d>& u,
                  const std::vector<Vector3d>& v) {
  const Matrix3d r0 = Align(ud, vd);
  const Vector3d axis = vd.normalized();
  double s = 0, c = 0;
  for (size_t i = 0; i < u.size(); ++i) {
    const Vector3d x = r0 * u[i], y = v[i];
    const Vector3d xp = x - axis * axis.dot(x), yp = y - axis * axis.dot(y);
    s += axis.dot(xp.cross(yp));
    c += xp.dot(yp);
  }
  return Eigen::AngleAxisd(std::atan2(s, c), axis).toRotationMatrix() * r0;
}

torch::Tensor BoneLengths(const torch::Tensor& poses, const torch::Tensor& child,
                          const torch::Tensor& parent) {
  return (poses.index_select(1, child) - poses.index_select(1, parent)).norm(2, -1);
}

}  // namespace

PoseRepair::PoseRepair(const ConstraintSetSpec& spec, const Skeleton& skeleton,
                       const PartPlan& parts, const PoseRepairOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = options;
  AnglePenaltyOptions every_bound;
  every_bound.cos_limit = 1.0;  // repair every bound, not only GSPS's training subset
  const ConstraintSet set = ConstraintSet::Build(spec, skeleton);
  m.original = AnglePenalty(set, every_bound);
  m.narrowed =
      AnglePenalty(ConstraintSet::Build(Narrowed(spec, options.margin_deg), skeleton), every_bound);
  for (const Constraint& c : set.constraints()) {
    std::set<int> joints;
    RegisterJoints(set, c.a, &joints);
    RegisterJoints(set, c.b, &joints);
    m.constraint_joints.push_back(std::move(joints));
  }
  for (const std::vector<int64_t>& nodes : parts.nodes) {
    std::set<int> joints;
    for (int64_t n : nodes) joints.insert(static_cast<int>(n) + 1);
    m.part_joints.push_back(std::move(joints));
  }
  m.num_joints = skeleton.num_joints();
  for (const std::vector<std::string>& group : spec.rigid) {
    std::vector<int> joints;
    for (const std::string& name : group) {
      const std::optional<int> j = skeleton.Find(name);
      if (!j || *j == 0) {
        throw std::invalid_argument(
            spec.source + ": rigid group joint '" + name + "' is " +
            (j ? "the root" : "not a joint of skeleton '" + skeleton.name() + "'") +
            "; expected a non-root joint");
      }
      joints.push_back(*j);
    }
    m.rigid.push_back(std::move(joints));
  }
  for (int j = 0; j < m.num_joints; ++j) m.subtree.push_back(skeleton.Subtree(j));
  std::vector<int64_t> child, parent;
  for (int j = 1; j < m.num_joints; ++j) {
    child.push_back(j);
    parent.push_back(skeleton.parent(j));
  }
  m.bone_child = torch::tensor(child, torch::kLong);
  m.bone_parent = torch::tensor(parent, torch::kLong);
}

PoseRepair::~PoseRepair() = default;
PoseRepair::PoseRepair(PoseRepair&&) noexcept = default;
PoseRepair& PoseRepair::operator=(PoseRepair&&) noexcept = default;

// Stage 1 for one part: each rigid group with joints in `own` put back on its template layout,
// turned to fit the joints decided earlier (when any) or its own joints.
void PoseRepair::RigidStage(const Impl& m, torch::Tensor& poses, const torch::Tensor& templates,
                            const std::set<int>& decided, const std::set<int>& own,
                            bool own_fixed) {
  if (m.rigid.empty()) return;
  const int64_t M = poses.size(0);
  const int J = m.num_joints;
  float* x = poses.data_ptr<float>();
  const float* t = templates.data_ptr<float>();
  for (const std::vector<int>& group : m.rigid) {
    std::vector<int> mine, before, all;
    for (int j : group) {
      if (own.count(j))
        mine.push_back(j);
      else if (decided.count(j))
        before.push_back(j);
    }
    if (mine.empty()) continue;
    // With nothing placed yet, a varying part fits the rotation to the whole group as predicted
    // (spreading the correction); a fixed part only to its own joints (identical in every sample).
    if (before.empty()) all = own_fixed ? mine : group;
    std::vector<Vector3d> u, v, um, vm, ua, va;
    for (int64_t i = 0; i < M; ++i) {
      float* p = x + i * J * 3;
      const float* q = t + i * J * 3;
      auto at = [](const float* a, int j) {
        return Vector3d(a[3 * j], a[3 * j + 1], a[3 * j + 2]);
      };
      u.clear(), v.clear(), um.clear(), vm.clear();
      for (int j : before) u.push_back(at(q, j)), v.push_back(at(p, j));
      for (int j : mine) um.push_back(at(q, j)), vm.push_back(at(p, j));
      ua.clear(), va.clear();
      for (int j : all) ua.push_back(at(q, j)), va.push_back(at(p, j));
      Matrix3d r;
      if (before.size() >= 2)
        r = FitRotation(u, v);
      else if (before.size() == 1)
        r = FitTwist(u[0], v[0], um, vm);
      else
        r = FitRotation(ua, va);
      for (size_t k = 0; k < mine.size(); ++k) {
        const Vector3d delta = r * um[k] - vm[k];
        for (int c : m.subtree[mine[k]]) {
          if (!own.count(c)) continue;
          for (int a = 0; a < 3; ++a) p[3 * c + a] += static_cast<float>(delta[a]);
        }
      }
    }
  }
}

PoseRepairStats PoseRepair::Repair(torch::Tensor& poses, const torch::Tensor& templates,
                                   const std::vector<bool>& fixed) const {
  const Impl& m = *impl_;
  const PoseRepairOptions& o = m.options;
  PoseRepairStats stats;
  stats.poses = poses.size(0);
  const int P = static_cast<int>(m.part_joints.size());
  std::vector<int> order;
  for (int p = 0; p < P; ++p)
    if (fixed.at(p)) order.push_back(p);
  for (int p = 0; p < P; ++p)
    if (!fixed.at(p)) order.push_back(p);

  torch::AutoGradMode grad_on(true);
  std::set<int> decided = {0};
  std::vector<char> repaired(static_cast<size_t>(poses.size(0)), 0);
  for (int p : order) {
    const std::set<int>& own = m.part_joints[p];
    RigidStage(m, poses, templates, decided, own, fixed.at(p));
    decided.insert(own.begin(), own.end());  // joints a constraint of this part may read
    std::vector<float> active(m.constraint_joints.size(), 0.0f);
    bool any = false;
    for (size_t c = 0; c < active.size(); ++c) {
      const std::set<int>& js = m.constraint_joints[c];
      const bool inside = std::includes(decided.begin(), decided.end(), js.begin(), js.end());
      const bool touches =
          std::any_of(js.begin(), js.end(), [&](int j) { return own.count(j) > 0; });
      if (inside && touches) active[c] = 1.0f, any = true;
    }
    if (!any) continue;
    const torch::Tensor mask = torch::tensor(active);
    torch::Tensor selected;
    {
      torch::NoGradGuard no_grad;
      selected = ((m.original->PerConstraint(poses) * mask).sum(-1) > 0).nonzero().view(-1);
    }
    if (selected.numel() == 0) continue;
    std::vector<float> movable_flags(m.num_joints, 0.0f);
    // Rigid-group joints were placed by stage 1 and stay; the rest of the part moves.
    for (int j : own) movable_flags[j] = 1.0f;
    for (const std::vector<int>& group : m.rigid)
      for (int j : group) movable_flags[j] = 0.0f;
    const torch::Tensor movable = torch::tensor(movable_flags).view({m.num_joints, 1});

    const torch::Tensor start = poses.index_select(0, selected);
    const torch::Tensor lengths = BoneLengths(start, m.bone_child, m.bone_parent);
    torch::Tensor x = start.clone().requires_grad_(true);
    // Adam (PyTorch's update, betas 0.9 / 0.999, eps 1e-8) written out so that each pose stops on
    // its own: once a check finds it inside every range it is frozen, so a pose's repair does not
    // depend on the other poses of its batch (nor on how many futures are asked for).
    constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kEps = 1e-8;
    torch::Tensor m1 = torch::zeros_like(start), m2 = torch::zeros_like(start);
    torch::Tensor moving = torch::ones({start.size(0), 1, 1});
    for (int step = 1; step <= o.max_steps; ++step) {
      const torch::Tensor loss =
          o.angle_weight * (m.narrowed->PerConstraint(x) * mask).sum() + (x - start).pow(2).sum() +
          o.bone_weight * (BoneLengths(x, m.bone_child, m.bone_parent) - lengths).pow(2).sum();
      const torch::Tensor grad = torch::autograd::grad({loss}, {x})[0] * movable;
      {
        torch::NoGradGuard no_grad;
        m1.mul_(kBeta1).add_(grad, 1 - kBeta1);
        m2.mul_(kBeta2).addcmul_(grad, grad, 1 - kBeta2);
        const double correction1 = 1 - std::pow(kBeta1, step),
                     correction2 = 1 - std::pow(kBeta2, step);
        const torch::Tensor denom = (m2.sqrt() / std::sqrt(correction2)).add_(kEps);
        x.sub_(m1 / denom * moving, o.step_m / correction1);
      }
      if (step % o.check_every == 0 || step == o.max_steps) {
        torch::NoGradGuard no_grad;
        const torch::Tensor broken = (m.original->PerConstraint(x) * mask).sum(-1) > 0;
        moving.mul_(broken.to(torch::kFloat).view({-1, 1, 1}));
        if (!broken.any().item<bool>()) break;
      }
    }
    torch::NoGradGuard no_grad;
    poses.index_copy_(0, selected, x.detach());
    const int64_t* idx = selected.data_ptr<int64_t>();
    for (int64_t i = 0; i < selected.numel(); ++i) repaired[idx[i]] = 1;
  }
  // Only repaired poses can still break a range: the others broke none in any part's check, and
  // each part moves only its own joints, whose constraints that part checked.
  std::vector<int64_t> touched;
  for (size_t i = 0; i < repaired.size(); ++i)
    if (repaired[i]) touched.push_back(static_cast<int64_t>(i));
  stats.repaired = static_cast<long long>(touched.size());
  if (!touched.empty()) {
    torch::NoGradGuard no_grad;
    const torch::Tensor moved = poses.index_select(0, torch::tensor(touched, torch::kLong));
    stats.still_broken = (m.original->PerConstraint(moved).sum(-1) > 0).sum().item<int64_t>();
  }
  return stats;
}

}  // namespace motionfork
