#include "imputation/bone_lengths.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace motionfork {

namespace {

int CheckedFrames(const Skeleton& skeleton, const std::vector<float>& positions,
                  const std::vector<uint8_t>& missing, const char* what) {
  const size_t F = static_cast<size_t>(skeleton.num_joints()) * 3;
  if (positions.size() % F != 0 || missing.size() != positions.size()) {
    throw std::invalid_argument(
        std::string(what) + ": expected [frames, " + std::to_string(skeleton.num_joints()) +
        ", 3] positions and a mask of the same size, got " + std::to_string(positions.size()) +
        " and " + std::to_string(missing.size()) + " values");
  }
  return static_cast<int>(positions.size() / F);
}

bool WhollyMissing(const std::vector<uint8_t>& missing, size_t i) {
  return missing[i] && missing[i + 1] && missing[i + 2];
}

bool WhollyObserved(const std::vector<uint8_t>& missing, size_t i) {
  return !missing[i] && !missing[i + 1] && !missing[i + 2];
}

}  // namespace

std::vector<ObservedBone> ObservedBones(const Skeleton& skeleton,
                                        const std::vector<float>& positions,
                                        const std::vector<uint8_t>& missing) {
  const int J = skeleton.num_joints();
  const int T = CheckedFrames(skeleton, positions, missing, "ObservedBones");
  std::vector<ObservedBone> out(J);
  std::vector<double> lengths;
  for (int j = 1; j < J; ++j) {
    const int p = skeleton.parent(j);
    lengths.clear();
    for (int t = 0; t < T; ++t) {
      const size_t a = (static_cast<size_t>(t) * J + j) * 3,
                   b = (static_cast<size_t>(t) * J + p) * 3;
      if (!WhollyObserved(missing, a) || !WhollyObserved(missing, b)) continue;
      double s = 0;
      for (int k = 0; k < 3; ++k) s += std::pow(double(positions[a + k]) - positions[b + k], 2);
      if (s > 0) lengths.push_back(std::sqrt(s));
    }
    if (lengths.empty()) continue;
    ObservedBone& bone = out[j];
    bone.frames = static_cast<int>(lengths.size());
    const size_t mid = lengths.size() / 2;
    std::nth_element(lengths.begin(), lengths.begin() + mid, lengths.end());
    bone.length = lengths[mid];
    for (double& x : lengths) x = std::abs(x - bone.length);
    const size_t p90 = std::min(lengths.size() - 1, lengths.size() * 9 / 10);
    std::nth_element(lengths.begin(), lengths.begin() + p90, lengths.end());
    bone.spread = lengths[p90];
  }
  return out;
}

std::vector<float> KeepBoneLengths(const Skeleton& skeleton, const std::vector<float>& filled,
                                   const std::vector<uint8_t>& missing, int sweeps) {
  const int J = skeleton.num_joints();
  const int T = CheckedFrames(skeleton, filled, missing, "KeepBoneLengths");
  const std::vector<ObservedBone> bones = ObservedBones(skeleton, filled, missing);
  std::vector<float> out = filled;
  std::vector<uint8_t> movable(J);
  for (int t = 0; t < T; ++t) {
    const size_t f = static_cast<size_t>(t) * J * 3;
    bool any = false;
    for (int j = 0; j < J; ++j) {
      movable[j] = WhollyMissing(missing, f + 3 * j);
      any = any || movable[j];
    }
    if (!any) continue;
    float* x = out.data() + f;
    for (int s = 0; s < sweeps; ++s) {
      for (int j = 1; j < J; ++j) {
        const int p = skeleton.parent(j);
        const int moving = movable[j] + movable[p];
        if (moving == 0 || !bones[j].rigid()) continue;
        double d[3], n = 0;
        for (int k = 0; k < 3; ++k) {
          d[k] = double(x[3 * j + k]) - x[3 * p + k];
          n += d[k] * d[k];
        }
        n = std::sqrt(n);
        if (n < 1e-9) continue;  // no direction to move along
        const double scale = (n - bones[j].length) / n / moving;
        for (int k = 0; k < 3; ++k) {
          if (movable[j]) x[3 * j + k] = static_cast<float>(x[3 * j + k] - scale * d[k]);
          if (movable[p]) x[3 * p + k] = static_cast<float>(x[3 * p + k] + scale * d[k]);
        }
      }
    }
  }
  return out;
}

}  // namespace motionfork
