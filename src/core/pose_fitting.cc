#include "core/pose_fitting.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/limbs.h"

namespace motionfork {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Rounds of the Procrustes mean of a branching joint's rest shape (each one a Kabsch fit per
// frame). The first round starts from frame 0's shape; human motion settles within a few.
constexpr int kProcrustesRounds = 3;

// The proper rotation R minimising sum_c w_c |R rest_c - target_c|^2 (Kabsch). With collinear
// directions the rotation about their line is arbitrary but the fit is still exact.
Matrix3d Kabsch(const Vector3d* rest, const Vector3d* target, const double* w, int n) {
  Matrix3d h = Matrix3d::Zero();
  for (int c = 0; c < n; ++c) h += w[c] * rest[c] * target[c].transpose();
  const Eigen::JacobiSVD<Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix3d d = Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) d(2, 2) = -1;
  return svd.matrixV() * d * svd.matrixU().transpose();
}

void CheckOptions(const PoseFitOptions& o) {
  if (!std::isfinite(o.tolerance)) {
    throw std::invalid_argument(
        "PoseFitOptions::tolerance: expected a finite number (metres), got " +
        std::to_string(o.tolerance));
  }
  if (!(o.min_bone_length > 0) || !std::isfinite(o.min_bone_length)) {
    throw std::invalid_argument(
        "PoseFitOptions::min_bone_length: expected a finite number > 0, got " +
        std::to_string(o.min_bone_length));
  }
}

}  // namespace

PoseFit FitPose(const Motion& motion, const PoseFitOptions& options) {
  CheckOptions(options);
  const int T = motion.num_frames(), J = motion.num_joints();
  if (J < 2) {
    throw std::invalid_argument(
        "FitPose: expected a skeleton with at least 2 joints (one bone), got " + std::to_string(J));
  }
  const Skeleton& skel = motion.skeleton();
  if (skel.is_anonymous()) {
    throw std::invalid_argument(
        "FitPose: skeleton '" + skel.name() +
        "' has no limb structure (its joints were read without a hierarchy, e.g. from .npy or "
        ".csv); expected a skeleton with parents (e.g. --skeleton bandai)");
  }
  if (T < 1) throw std::invalid_argument("FitPose: expected at least 1 frame, got 0");
  Limbs limbs;
  try {
    limbs = ToLimbs(motion, static_cast<float>(options.min_bone_length));
  } catch (const std::invalid_argument& e) {
    std::string what = e.what();
    if (what.rfind("ToLimbs: ", 0) == 0) what.erase(0, 9);
    throw std::invalid_argument("FitPose: " + what);
  }

  std::vector<std::vector<int>> children(J);
  for (int j = 1; j < J; ++j) children[skel.parent(j)].push_back(j);
  // Unit direction of the bone ending at joint c (> 0) in frame t, world frame.
  auto direction = [&](int t, int c) {
    const float* d = &limbs.directions[3 * (static_cast<size_t>(t) * (J - 1) + c - 1)];
    return Vector3d(d[0], d[1], d[2]);
  };
  std::vector<double> length(J, 0.0);  // rest length of the bone ending at each joint, metres
  for (int c = 1; c < J; ++c) {
    double sum = 0;
    for (int t = 0; t < T; ++t) sum += limbs.lengths[static_cast<size_t>(t) * (J - 1) + c - 1];
    length[c] = sum / T;
  }

  PoseFit fit;
  fit.num_frames = T;
  fit.num_joints = J;
  fit.offsets.assign(3 * static_cast<size_t>(J), 0.0);
  fit.translated.assign(J, false);
  fit.translated[0] = true;
  fit.translations.assign(3 * static_cast<size_t>(T) * J, 0.0);
  fit.rotations.assign(9 * static_cast<size_t>(T) * J, 0.0);
  for (int a = 0; a < 3; ++a) fit.offsets[a] = motion.at(0, 0)[a];
  for (int t = 0; t < T; ++t) {
    double* root = &fit.translations[3 * static_cast<size_t>(t) * J];
    for (int a = 0; a < 3; ++a) root[a] = motion.at(t, 0)[a];
  }

  const double tol = options.tolerance;
  // Bones that vary in length beyond the tolerance (kExact): translated, and left out of their
  // parent's rotation fit.
  std::vector<bool> stretchy(J, false);
  if (options.lengths == BoneLengths::kExact && tol >= 0) {
    for (int c = 1; c < J; ++c) {
      for (int t = 0; t < T && !stretchy[c]; ++t) {
        stretchy[c] =
            std::abs(limbs.lengths[static_cast<size_t>(t) * (J - 1) + c - 1] - length[c]) > tol;
      }
    }
  }

  std::vector<Matrix3d> world(static_cast<size_t>(T) * J);  // [T, J] joint frame -> world
  std::vector<Matrix3d> local(T);                           // one joint's rotations
  std::vector<Vector3d> target, rest, moved;                // [T, n], [n], [n]
  std::vector<double> weight;
  for (int j = 0; j < J; ++j) {
    // The children steering this joint's rotation first, then the stretchy ones.
    std::vector<int> ch;
    for (int pass = 0; pass < 2; ++pass) {
      for (int c : children[j]) {
        if (stretchy[c] == (pass == 1)) ch.push_back(c);
      }
    }
    const int n = static_cast<int>(ch.size());
    const int fitted =
        static_cast<int>(std::count_if(ch.begin(), ch.end(), [&](int c) { return !stretchy[c]; }));
    // Children's directions in this joint's parent frame: [T, n].
    target.resize(static_cast<size_t>(T) * n);
    for (int t = 0; t < T; ++t) {
      const Matrix3d parent = j == 0 ? Matrix3d::Identity() : world[t * J + skel.parent(j)];
      for (int k = 0; k < n; ++k) target[t * n + k] = parent.transpose() * direction(t, ch[k]);
    }
    rest.assign(n, Vector3d::Zero());
    if (fitted == 0) {
      std::fill(local.begin(), local.end(), Matrix3d::Identity());
    } else if (fitted == 1) {
      for (int t = 0; t < T; ++t) rest[0] += target[t * n];
      // A direction spread evenly over the sphere has no mean; frame 0's then.
      rest[0] = rest[0].norm() > 1e-6 * T ? rest[0].normalized() : target[0];
      for (int t = 0; t < T; ++t) {
        local[t] = Eigen::Quaterniond::FromTwoVectors(rest[0], target[t * n]).toRotationMatrix();
      }
    } else {
      weight.assign(fitted, 0.0);
      for (int k = 0; k < fitted; ++k) weight[k] = length[ch[k]];
      std::copy(target.begin(), target.begin() + fitted, rest.begin());
      for (int round = 0;; ++round) {
        for (int t = 0; t < T; ++t)
          local[t] = Kabsch(rest.data(), &target[t * n], weight.data(), fitted);
        if (round == kProcrustesRounds) break;
        moved.assign(fitted, Vector3d::Zero());
        for (int t = 0; t < T; ++t) {
          for (int k = 0; k < fitted; ++k) moved[k] += local[t].transpose() * target[t * n + k];
        }
        for (int k = 0; k < fitted; ++k) {
          if (moved[k].norm() > 1e-6 * T) rest[k] = moved[k].normalized();
        }
      }
    }
    for (int k = 0; k < n; ++k) {
      const int c = ch[k];
      if (k >= fitted) {  // stretchy: rest along its mean direction in this joint's frame
        for (int t = 0; t < T; ++t) rest[k] += local[t].transpose() * target[t * n + k];
        rest[k] = rest[k].norm() > 1e-6 * T ? rest[k].normalized()
                                            : Vector3d(local[0].transpose() * target[k]);
      }
      for (int a = 0; a < 3; ++a) fit.offsets[3 * c + a] = length[c] * rest[k][a];
      double misfit = 0;  // metres, at the mean length
      for (int t = 0; t < T && k < fitted; ++t) {
        misfit = std::max(misfit, length[c] * (local[t] * rest[k] - target[t * n + k]).norm());
      }
      fit.translated[c] = stretchy[c] || (tol >= 0 && misfit > tol);
      for (int t = 0; t < T; ++t) {
        const double len =
            stretchy[c] ? limbs.lengths[static_cast<size_t>(t) * (J - 1) + c - 1] : length[c];
        const Vector3d v = fit.translated[c]
                               ? Vector3d(len * (local[t].transpose() * target[t * n + k]))
                               : Vector3d(length[c] * rest[k]);
        double* out = &fit.translations[3 * (static_cast<size_t>(t) * J + c)];
        for (int a = 0; a < 3; ++a) out[a] = v[a];
      }
    }
    for (int t = 0; t < T; ++t) {
      world[t * J + j] = j == 0 ? local[t] : Matrix3d(world[t * J + skel.parent(j)] * local[t]);
      double* out = &fit.rotations[9 * (static_cast<size_t>(t) * J + j)];
      for (int r = 0; r < 3; ++r) {
        for (int col = 0; col < 3; ++col) out[3 * r + col] = local[t](r, col);
      }
    }
  }
  return fit;
}

Motion PoseFitPositions(const PoseFit& fit, std::shared_ptr<const Skeleton> skeleton, double fps) {
  if (!skeleton || skeleton->num_joints() != fit.num_joints) {
    throw std::invalid_argument("PoseFitPositions: expected a skeleton of " +
                                std::to_string(fit.num_joints) + " joints, got " +
                                std::to_string(skeleton ? skeleton->num_joints() : 0));
  }
  const int T = fit.num_frames, J = fit.num_joints;
  std::vector<float> positions(static_cast<size_t>(T) * J * 3);
  std::vector<Matrix3d> world(J);
  std::vector<Vector3d> at(J);
  for (int t = 0; t < T; ++t) {
    for (int j = 0; j < J; ++j) {
      const Matrix3d r =
          Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(fit.rotation(t, j));
      const Vector3d tr = Eigen::Map<const Vector3d>(fit.translation(t, j));
      const int p = skeleton->parent(j);
      world[j] = p < 0 ? r : Matrix3d(world[p] * r);
      at[j] = p < 0 ? tr : Vector3d(at[p] + world[p] * tr);
      for (int a = 0; a < 3; ++a)
        positions[(static_cast<size_t>(t) * J + j) * 3 + a] = static_cast<float>(at[j][a]);
    }
  }
  return Motion(std::move(skeleton), fps, std::move(positions));
}

}  // namespace motionfork
