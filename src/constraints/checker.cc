#include "constraints/checker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "constraints/vector_registers.h"
#include "core/enum_names.h"

namespace motionfork {

namespace {
constexpr EnumName<AngleStatus> kAngleStatusNames[] = {{AngleStatus::kInside, "inside"},
                                                       {AngleStatus::kBelow, "below"},
                                                       {AngleStatus::kAbove, "above"},
                                                       {AngleStatus::kDegenerate, "degenerate"}};
}  // namespace

const char* ToString(AngleStatus status) { return NameOf(status, kAngleStatusNames); }

void Validate(const DegeneracyOptions& o) {
  if (!(o.min_bone_length >= 0) || !std::isfinite(o.min_bone_length)) {
    throw std::invalid_argument(
        "DegeneracyOptions.min_bone_length = " + std::to_string(o.min_bone_length) +
        " breaks the rule: a finite length >= 0 metres");
  }
  if (!(o.min_normal_sine >= 0 && o.min_normal_sine < 1)) {
    throw std::invalid_argument(
        "DegeneracyOptions.min_normal_sine = " + std::to_string(o.min_normal_sine) +
        " breaks the rule: 0 <= value < 1");
  }
}

AngleChecker::AngleChecker(const ConstraintSet& set, const DegeneracyOptions& options)
    : set_(set), options_(options) {
  Validate(options_);
}

void AngleChecker::Run(const float* positions, int num_frames, float* angles_deg,
                       AngleStatus* status) const {
  if (num_frames < 0) {
    throw std::invalid_argument("AngleChecker::Run: expected num_frames >= 0, got " +
                                std::to_string(num_frames));
  }
  if (num_frames > 0 && !positions)
    throw std::invalid_argument("AngleChecker::Run: positions is null");
  const std::vector<VectorOp>& ops = set_.ops();
  const std::vector<Constraint>& cons = set_.constraints();
  const int R = static_cast<int>(ops.size());
  const int C = static_cast<int>(cons.size());
  const size_t stride = static_cast<size_t>(set_.num_joints()) * 3;
  // Registers: x, y, z, squared length; a register is undefined when its flag is set.
  std::vector<float> reg(static_cast<size_t>(R) * 4);
  std::vector<uint8_t> undefined(R);
  std::vector<float> lower(C), upper(C);
  std::vector<int> ra(C), rb(C);
  for (int c = 0; c < C; ++c) {
    lower[c] = static_cast<float>(cons[c].lower_deg);
    upper[c] = static_cast<float>(cons[c].upper_deg);
    ra[c] = cons[c].a;
    rb[c] = cons[c].b;
  }
  const float min_len2 = options_.min_bone_length * options_.min_bone_length;
  const float min_sin2 = options_.min_normal_sine * options_.min_normal_sine;
  constexpr float kDegrees = static_cast<float>(180.0 / 3.14159265358979323846);

  for (int t = 0; t < num_frames; ++t) {
    const float* f = positions + static_cast<size_t>(t) * stride;
    for (int r = 0; r < R; ++r) {
      const VectorOp& op = ops[r];
      float* out = &reg[4 * r];
      if (op.kind == VectorOp::Kind::kBone) {
        undefined[r] = BoneRegister(f, op.x, op.y, min_len2, out);
      } else {
        undefined[r] = CrossRegister(&reg[4 * op.x], &reg[4 * op.y],
                                     undefined[op.x] | undefined[op.y], min_sin2, out);
      }
    }
    float* angle_row = angles_deg ? angles_deg + static_cast<size_t>(t) * C : nullptr;
    AngleStatus* status_row = status ? status + static_cast<size_t>(t) * C : nullptr;
    for (int c = 0; c < C; ++c) {
      const int a = ra[c], b = rb[c];
      float angle;
      AngleStatus s;
      if (undefined[a] | undefined[b]) {
        angle = kUndefinedAngle;
        s = AngleStatus::kDegenerate;
      } else {
        const float* u = &reg[4 * a];
        const float* v = &reg[4 * b];
        float cosine = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / std::sqrt(u[3] * v[3]);
        cosine = std::min(1.0f, std::max(-1.0f, cosine));
        angle = std::acos(cosine) * kDegrees;
        s = angle < lower[c] ? AngleStatus::kBelow
                             : (angle > upper[c] ? AngleStatus::kAbove : AngleStatus::kInside);
      }
      if (angle_row) angle_row[c] = angle;
      if (status_row) status_row[c] = s;
    }
  }
}

CheckResult Check(const ConstraintSet& set, const Motion& motion,
                  const DegeneracyOptions& options) {
  if (motion.num_joints() != set.num_joints()) {
    throw std::invalid_argument("Check: constraint set '" + set.name() + "' was built for " +
                                std::to_string(set.num_joints()) + " joints (skeleton '" +
                                set.skeleton_name() + "'), got a motion with " +
                                std::to_string(motion.num_joints()) + " joints");
  }
  CheckResult r;
  r.num_frames = motion.num_frames();
  r.num_constraints = set.num_constraints();
  const size_t n = static_cast<size_t>(r.num_frames) * r.num_constraints;
  r.angles_deg.resize(n);
  r.status.resize(n);
  AngleChecker(set, options)
      .Run(motion.positions().data(), r.num_frames, r.angles_deg.data(), r.status.data());
  return r;
}

float ExcessDegrees(const Constraint& c, float angle_deg) {
  if (angle_deg < 0) return 0;  // undefined
  if (angle_deg < c.lower_deg) return static_cast<float>(c.lower_deg - angle_deg);
  if (angle_deg > c.upper_deg) return static_cast<float>(angle_deg - c.upper_deg);
  return 0;
}

CheckSummary Summarize(const ConstraintSet& set, const CheckResult& result, int max_worst) {
  if (result.num_constraints != set.num_constraints()) {
    throw std::invalid_argument("Summarize: expected results for " +
                                std::to_string(set.num_constraints()) + " constraints, got " +
                                std::to_string(result.num_constraints));
  }
  const int C = result.num_constraints;
  CheckSummary s;
  s.frames = result.num_frames;
  s.constraints.resize(C);
  std::vector<bool> seen(C, false);
  std::vector<FrameViolation> violating;
  for (int t = 0; t < result.num_frames; ++t) {
    bool violated = false, degenerate = false;
    FrameViolation fv;
    fv.frame = t;
    for (int c = 0; c < C; ++c) {
      ConstraintSummary& cs = s.constraints[c];
      const AngleStatus st = result.at(t, c);
      const float angle = result.angle(t, c);
      if (st == AngleStatus::kDegenerate) {
        ++cs.degenerate;
        degenerate = true;
        continue;
      }
      if (!seen[c]) {
        cs.min_deg = cs.max_deg = angle;
        seen[c] = true;
      }
      cs.min_deg = std::min(cs.min_deg, angle);
      cs.max_deg = std::max(cs.max_deg, angle);
      if (st == AngleStatus::kInside) continue;
      (st == AngleStatus::kBelow ? cs.below : cs.above)++;
      violated = true;
      const float excess = ExcessDegrees(set.constraint(c), angle);
      fv.excess_deg += excess;
      fv.constraints.push_back(c);
      if (cs.worst_frame < 0 || excess > cs.worst_excess_deg) {
        cs.worst_frame = t;
        cs.worst_excess_deg = excess;
      }
    }
    s.violating_frames += violated;
    s.degenerate_frames += degenerate;
    s.valid_frames += !violated && !degenerate;
    if (violated) violating.push_back(std::move(fv));
  }
  for (ConstraintSummary& cs : s.constraints) {
    cs.violation_rate = s.frames ? double(cs.violations()) / s.frames : 0.0;
  }
  const size_t keep = std::min(violating.size(), static_cast<size_t>(std::max(0, max_worst)));
  std::partial_sort(violating.begin(), violating.begin() + keep, violating.end(),
                    [](const FrameViolation& x, const FrameViolation& y) {
                      return x.excess_deg != y.excess_deg ? x.excess_deg > y.excess_deg
                                                          : x.frame < y.frame;
                    });
  violating.resize(keep);
  s.worst_frames = std::move(violating);
  return s;
}

}  // namespace motionfork
