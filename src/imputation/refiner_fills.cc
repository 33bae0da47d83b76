#include "imputation/refiner_fills.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "imputation/bone_lengths.h"
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

int RefinerGapBucket(float before, float after, float edge_speed, bool crowded_frame) {
  int length_class = 7;  // not bracketed
  if (before < kRefinerGapCap && after < kRefinerGapCap) {
    const int length = static_cast<int>(before + after) - 1;
    length_class = 0;
    for (int upper = 1; length > upper && length_class < 6; upper *= 2) ++length_class;
  }
  const int speed_class = edge_speed < kRefinerSlow ? 0 : edge_speed <= kRefinerFast ? 1 : 2;
  return (3 * length_class + speed_class) * 2 + (crowded_frame ? 1 : 0);
}

std::string RefinerGapBucketName(int bucket) {
  static const char* kLengths[] = {"gap 1",    "gap 2",     "gap 3-4", "gap 5-8",
                                   "gap 9-16", "gap 17-32", "gap 33+", "unbracketed"};
  static const char* kSpeeds[] = {"slow", "medium", "fast"};
  if (bucket < 0 || bucket >= kRefinerGapBuckets)
    throw std::invalid_argument("RefinerGapBucketName: no bucket " + std::to_string(bucket));
  return std::string(kLengths[bucket / 6]) + ", " + kSpeeds[bucket / 2 % 3] +
         (bucket % 2 ? ", crowded" : ", sparse");
}

float RefinerEdgeSpeed(const RefinerFills& f, size_t row, int coord) {
  const size_t N = static_cast<size_t>(f.coords), T = static_cast<size_t>(f.frames);
  const size_t first = row - row % T, last = first + T - 1;  // the window's rows
  const size_t i = row * N + coord;
  auto at = [&](size_t r) { return f.spline[r * N + coord]; };
  float speed = 0;
  if (f.before[i] < kRefinerGapCap) {
    const size_t edge = row - static_cast<size_t>(f.before[i]);
    if (edge > first) speed = std::max(speed, std::abs(at(edge) - at(edge - 1)));
  }
  if (f.after[i] < kRefinerGapCap) {
    const size_t edge = row + static_cast<size_t>(f.after[i]);
    if (edge < last) speed = std::max(speed, std::abs(at(edge + 1) - at(edge)));
  }
  if (f.before[i] < kRefinerGapCap && f.after[i] < kRefinerGapCap) {
    speed = std::max(speed, std::abs(at(row + static_cast<size_t>(f.after[i])) -
                                     at(row - static_cast<size_t>(f.before[i]))) /
                                (f.before[i] + f.after[i]));
  }
  return speed;
}

std::vector<int> RefinerGapBuckets(const RefinerFills& f) {
  const size_t N = static_cast<size_t>(f.coords), frames = N == 0 ? 0 : f.mask.size() / N;
  std::vector<int> buckets(f.mask.size(), -1);
  for (size_t t = 0; t < frames; ++t) {
    const uint8_t* m = f.mask.data() + t * N;
    const size_t missing = static_cast<size_t>(std::count(m, m + N, uint8_t{1}));
    const bool crowded = 4 * missing > N;
    for (size_t v = 0; v < N; ++v) {
      const size_t i = t * N + v;
      if (m[v]) {
        buckets[i] = RefinerGapBucket(f.before[i], f.after[i],
                                      RefinerEdgeSpeed(f, t, static_cast<int>(v)), crowded);
      }
    }
  }
  return buckets;
}

std::vector<float> RefinerValueWeights(const RefinerFills& f, const std::vector<double>& weights) {
  if (!weights.empty() && weights.size() != static_cast<size_t>(kRefinerGapBuckets)) {
    throw std::invalid_argument("refiner weights: expected " + std::to_string(kRefinerGapBuckets) +
                                ", got " + std::to_string(weights.size()));
  }
  const std::vector<int> buckets = RefinerGapBuckets(f);
  std::vector<float> w(buckets.size(), 0.0f);
  for (size_t i = 0; i < w.size(); ++i) {
    if (buckets[i] >= 0) w[i] = weights.empty() ? 1.0f : static_cast<float>(weights[buckets[i]]);
  }
  return w;
}

std::vector<float> BlendRefinerFills(const Skeleton& skeleton, const RefinerFills& f,
                                     const std::vector<float>& refined,
                                     const ImputationBlend& blend) {
  const size_t N = static_cast<size_t>(f.coords), T = static_cast<size_t>(f.frames);
  if (refined.size() != T * N || f.spline.size() != T * N || f.local.size() != T * N ||
      static_cast<size_t>(3 * (skeleton.num_joints() - 1)) != N) {
    throw std::invalid_argument("BlendRefinerFills: expected one window of " + std::to_string(T) +
                                " x " + std::to_string(N) + " values on the skeleton's " +
                                std::to_string(skeleton.num_joints()) + " joints, got " +
                                std::to_string(refined.size()));
  }
  const std::vector<float> a = RefinerValueWeights(f, blend.refiner);
  const std::vector<float> b = blend.local.empty() ? std::vector<float>(a.size(), 0.0f)
                                                   : RefinerValueWeights(f, blend.local);
  std::vector<float> out = refined;
  for (size_t i = 0; i < out.size(); ++i) {
    if (f.mask[i])
      out[i] = f.spline[i] + a[i] * (refined[i] - f.spline[i]) + b[i] * (f.local[i] - f.spline[i]);
  }
  // The last stages: the smooth path, then the Gaussian's conditional means.
  auto finish = [&](const std::vector<float>& v) {
    const std::vector<float> smooth = SmoothFilledValues(v, f.mask, f.coords, blend.smoothing);
    return blend.gaussian
               ? FillFromWindowGaussian(*blend.gaussian, smooth, f.mask, blend.gaussian_scope)
               : smooth;
  };
  if (!blend.keep_bones) return finish(out);
  const size_t F = N + 3;
  const std::vector<float> kept = KeepBoneLengths(skeleton, WithRootAtOrigin(out.data(), T, N),
                                                  WithRootAtOrigin(f.mask.data(), T, N));
  const std::vector<float> share = blend.bones.empty() ? std::vector<float>(out.size(), 1.0f)
                                                       : RefinerValueWeights(f, blend.bones);
  for (size_t t = 0; t < T; ++t) {
    for (size_t v = 0; v < N; ++v) {
      const size_t i = t * N + v;
      out[i] += share[i] * (kept[t * F + 3 + v] - out[i]);
    }
  }
  return finish(out);
}

double AdaptValues(const ImputationBlend& blend, int bucket) {
  const std::vector<double>& v = blend.adapt_values;
  if (v.empty()) return 0;
  if (v.size() == 1) return v[0];
  if (v.size() != static_cast<size_t>(kRefinerGapLengths) || bucket < 0 ||
      bucket >= kRefinerGapBuckets) {
    throw std::invalid_argument("adapt values: expected 1 or " +
                                std::to_string(kRefinerGapLengths) + " (one per gap length), got " +
                                std::to_string(v.size()));
  }
  return v[bucket / (kRefinerGapBuckets / kRefinerGapLengths)];
}

bool AdaptsToMotion(const ImputationBlend& blend) {
  return std::any_of(blend.adapt_values.begin(), blend.adapt_values.end(),
                     [](double v) { return v > 0; });
}

void AppendRefinerFills(const RefinerFills& f, RefinerFills* all) {
  all->frames = f.frames;
  all->coords = f.coords;
  all->spline.insert(all->spline.end(), f.spline.begin(), f.spline.end());
  all->linear.insert(all->linear.end(), f.linear.begin(), f.linear.end());
  all->rigid.insert(all->rigid.end(), f.rigid.begin(), f.rigid.end());
  all->local.insert(all->local.end(), f.local.begin(), f.local.end());
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
  f.coords = N;
  f.spline = RootRelative(
      InterpolateMissing(positions, missing, J, Interpolation::kCubicSpline, fallback), T, J);
  f.linear = RootRelative(
      InterpolateMissing(positions, missing, J, Interpolation::kLinear, fallback), T, J);
  f.rigid = RootRelative(RigidLimbFill(skeleton, positions, missing, fallback), T, J);
  f.local = RootRelative(
      InterpolateMissing(positions, missing, J, Interpolation::kLocalPolynomial, fallback), T, J);
  f.mask.resize(static_cast<size_t>(T) * N);
  for (int t = 0; t < T; ++t) {
    for (int v = 0; v < N; ++v)
      f.mask[static_cast<size_t>(t) * N + v] = missing[static_cast<size_t>(t) * J * 3 + 3 + v];
  }
  f.before = GapDistance(f.mask, T, N, 1);
  f.after = GapDistance(f.mask, T, N, -1);
  f.fallback = fallback;
  return f;
}

}  // namespace motionfork
