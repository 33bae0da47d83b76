#include "core/limbs.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace motionfork {

Limbs ToLimbs(const Motion& motion, float min_length) {
  const int T = motion.num_frames(), J = motion.num_joints();
  const Skeleton& s = motion.skeleton();
  Limbs out;
  out.num_frames = T;
  out.num_limbs = J - 1;
  out.root.resize(static_cast<size_t>(T) * 3);
  out.directions.resize(static_cast<size_t>(T) * (J - 1) * 3);
  out.lengths.resize(static_cast<size_t>(T) * (J - 1));
  for (int t = 0; t < T; ++t) {
    for (int a = 0; a < 3; ++a) out.root[3 * t + a] = motion.at(t, 0)[a];
    for (int j = 1; j < J; ++j) {
      const float* c = motion.at(t, j);
      const float* p = motion.at(t, s.parent(j));
      const double v[3] = {double(c[0]) - p[0], double(c[1]) - p[1], double(c[2]) - p[2]};
      const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (!(len >= min_length)) {
        throw std::invalid_argument("ToLimbs: frame " + std::to_string(t) + ": bone '" +
                                    s.joint_name(s.parent(j)) + "' -> '" + s.joint_name(j) +
                                    "' has length " + std::to_string(len) +
                                    " m, expected at least " + std::to_string(min_length) +
                                    " m (a zero-length bone has no direction)");
      }
      const size_t k = static_cast<size_t>(t) * (J - 1) + (j - 1);
      out.lengths[k] = static_cast<float>(len);
      for (int a = 0; a < 3; ++a) out.directions[3 * k + a] = static_cast<float>(v[a] / len);
    }
  }
  return out;
}

Motion FromLimbs(std::shared_ptr<const Skeleton> skeleton, double fps, const Limbs& limbs) {
  if (!skeleton) throw std::invalid_argument("FromLimbs: expected a skeleton, got null");
  const int T = limbs.num_frames, J = skeleton->num_joints();
  const size_t nl = static_cast<size_t>(T) * (J - 1);
  if (limbs.num_limbs != J - 1 || limbs.root.size() != static_cast<size_t>(T) * 3 ||
      limbs.directions.size() != nl * 3 || limbs.lengths.size() != nl) {
    throw std::invalid_argument("FromLimbs: expected " + std::to_string(J - 1) + " limbs for " +
                                std::to_string(T) + " frames of skeleton '" + skeleton->name() +
                                "', got " + std::to_string(limbs.num_limbs) +
                                " limbs and arrays of mismatched sizes");
  }
  std::vector<double> world(static_cast<size_t>(J) * 3);
  std::vector<float> out(static_cast<size_t>(T) * J * 3);
  for (int t = 0; t < T; ++t) {
    for (int a = 0; a < 3; ++a) world[a] = limbs.root[3 * t + a];
    for (int j = 1; j < J; ++j) {
      const size_t k = static_cast<size_t>(t) * (J - 1) + (j - 1);
      const float* d = &limbs.directions[3 * k];
      const double n = std::sqrt(double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2]);
      if (!(n > 0) || !std::isfinite(n)) {
        throw std::invalid_argument("FromLimbs: frame " + std::to_string(t) + ", joint '" +
                                    skeleton->joint_name(j) + "': direction has no length");
      }
      const int p = skeleton->parent(j);
      for (int a = 0; a < 3; ++a) world[3 * j + a] = world[3 * p + a] + limbs.lengths[k] * d[a] / n;
    }
    for (int i = 0; i < J * 3; ++i) out[static_cast<size_t>(t) * J * 3 + i] = float(world[i]);
  }
  return Motion(std::move(skeleton), fps, std::move(out));
}

}  // namespace motionfork
