#include "imputation/refiner_fills.h"

#include "imputation/interpolation_fill.h"

namespace motionfork {

namespace {

// Root-relative coordinates without the root of positions [T, J, 3].
std::vector<float> RootRelative(const std::vector<float>& p, int frames, int joints) {
  const int N = 3 * (joints - 1);
  std::vector<float> out(static_cast<size_t>(frames) * N);
  for (int t = 0; t < frames; ++t) {
    const size_t f = static_cast<size_t>(t) * joints * 3;
    for (int v = 0; v < N; ++v) out[static_cast<size_t>(t) * N + v] = p[f + 3 + v] - p[f + v % 3];
  }
  return out;
}

}  // namespace

RefinerFills MakeRefinerFills(const Skeleton& skeleton, const std::vector<float>& positions,
                              const std::vector<uint8_t>& missing,
                              const std::vector<float>& fallback) {
  const int J = skeleton.num_joints(), T = static_cast<int>(positions.size() / (3 * J)),
            N = 3 * (J - 1);
  RefinerFills f;
  f.frames = T;
  f.spline = RootRelative(
      InterpolateMissing(positions, missing, J, Interpolation::kCubicSpline, fallback), T, J);
  f.linear = RootRelative(
      InterpolateMissing(positions, missing, J, Interpolation::kLinear, fallback), T, J);
  f.rigid = RootRelative(RigidLimbFill(skeleton, positions, missing, fallback), T, J);
  f.mask.resize(static_cast<size_t>(T) * N);
  for (int t = 0; t < T; ++t) {
    for (int v = 0; v < N; ++v)
      f.mask[static_cast<size_t>(t) * N + v] = missing[static_cast<size_t>(t) * J * 3 + 3 + v];
  }
  return f;
}

}  // namespace motionfork
