#include "imputation/refiner_fills.h"

#include <algorithm>

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

// Per value of mask [T, N], frames to the nearest 0 at or before it (`step` +1) or at or after it
// (`step` -1), capped at kRefinerGapCap.
std::vector<float> GapDistance(const std::vector<uint8_t>& mask, int T, int N, int step) {
  std::vector<float> d(mask.size());
  for (int v = 0; v < N; ++v) {
    float run = kRefinerGapCap;
    for (int k = 0; k < T; ++k) {
      const size_t i = static_cast<size_t>(step > 0 ? k : T - 1 - k) * N + v;
      run = mask[i] ? std::min(run + 1, kRefinerGapCap) : 0;
      d[i] = run;
    }
  }
  return d;
}

}  // namespace

void AppendRefinerFills(const RefinerFills& f, RefinerFills* all) {
  all->frames = f.frames;
  all->spline.insert(all->spline.end(), f.spline.begin(), f.spline.end());
  all->linear.insert(all->linear.end(), f.linear.begin(), f.linear.end());
  all->rigid.insert(all->rigid.end(), f.rigid.begin(), f.rigid.end());
  all->mask.insert(all->mask.end(), f.mask.begin(), f.mask.end());
  all->before.insert(all->before.end(), f.before.begin(), f.before.end());
  all->after.insert(all->after.end(), f.after.begin(), f.after.end());
}

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
  f.before = GapDistance(f.mask, T, N, 1);
  f.after = GapDistance(f.mask, T, N, -1);
  return f;
}

}  // namespace motionfork
