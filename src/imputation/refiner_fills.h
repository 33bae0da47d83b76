// The imputation refiner's inputs over a whole motion (no LibTorch): the classical fills of its
// missing values (interpolation_fill.h: cubic spline, linear, rigid limb; the fallback pose where
// a value is never observed) as root-relative coordinates without the root, [T, N] with N = 3
// per non-root joint, the mask in the same layout, and each value's distance in frames to the
// nearest observed value of its coordinate before and after it (0 where observed; capped at
// kRefinerGapCap, which also stands for "none"). Several windows of the same length can be held
// one after the other (AppendRefinerFills).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/skeleton.h"
#include "imputation/fill_smoothing.h"
#include "imputation/window_gaussian.h"

namespace motionfork {

constexpr float kRefinerGapCap = 64;
// The refiner's correction counts d^2 / (d^2 + g^2) at d frames from the nearest observed value
// (HgvaeTensors::Refined): a tenth at 1 frame, half at 3, 0.9 at 9.
constexpr float kRefinerGateFrames = 3;

struct RefinerFills {
  int frames = 0;                            // per window
  int coords = 0;                            // N
  std::vector<float> spline, linear, rigid;  // [T, N], metres, root-relative
  std::vector<float> local;                  // [T, N], Interpolation::kLocalPolynomial (no input)
  std::vector<uint8_t> mask;                 // [T, N], 1 = missing
  std::vector<float> before, after;          // [T, N], frames to the nearest observed value
  std::vector<float> fallback;               // [J, 3] root-relative: where nothing is observed
};

// The refiner's correction is calibrated per bucket of missing values (HgvaeManifest's
// refiner_weights, fitted on held-out clips by imputation/training/refiner_calibration.h): the
// length of the value's gap (1, 2, 3-4, 5-8, 9-16, 17-32, 33 or more frames; or not bracketed by
// observed values within kRefinerGapCap frames) x how fast its coordinate moves at the gap's edges
// (RefinerEdgeSpeed: slow below kRefinerSlow, fast above kRefinerFast, metres per frame) x whether
// more than a quarter of its frame's values are missing (the context a gap has around it).
// Bucket = (3 * length class + speed class) * 2 + crowded.
constexpr int kRefinerGapBuckets = 48;
constexpr int kRefinerGapLengths = 8;  // the length classes; a bucket's is bucket / 6
constexpr float kRefinerSlow = 0.003f, kRefinerFast = 0.015f;
int RefinerGapBucket(float before, float after, float edge_speed, bool crowded_frame);
std::string RefinerGapBucketName(int bucket);  // "gap 3-4, slow, sparse"
// The weight of every value of every window of f ([T, N] each; 0 where observed) for weights
// [kRefinerGapBuckets]; empty weights: 1 for every missing value.
std::vector<float> RefinerValueWeights(const RefinerFills& f, const std::vector<double>& weights);
// How fast coordinate `coord` moves at the edges of the gap holding row `row` (of every window's
// rows one after another), metres per frame: the largest of the frame-to-frame change of the fill
// just outside each edge and the mean change across the gap (0 where nothing is observed).
float RefinerEdgeSpeed(const RefinerFills& f, size_t row, int coord);
// Each value's bucket as above ([T, N] per window; -1 where observed).
std::vector<int> RefinerGapBuckets(const RefinerFills& f);

// How the calibrated output is put together from the spline, the refiner's output and the local
// polynomial (HgvaeManifest's refiner_weights, refiner_local_weights, refiner_keep_bones): each
// missing value is spline + a (refined - spline) + b (local - spline) with a and b its bucket's
// weights, then, with keep_bones, the rigid bones of every frame are kept at the lengths
// observed in the motion (bone_lengths.h).
struct ImputationBlend {
  std::vector<double> refiner;  // a per bucket [kRefinerGapBuckets]; empty: 1 everywhere
  std::vector<double> local;    // b per bucket; empty: 0 everywhere
  bool keep_bones = false;
  // With keep_bones, how much of the bones' correction each bucket takes (empty: all of it).
  std::vector<double> bones;
  // > 0: a, b and the bones' share are first adapted to the motion (refiner_adaptation.h), pulled
  // towards the weights above as if by this many values; 0: used as they are. One value for every
  // bucket, or one per gap length class [kRefinerGapLengths]; empty: 0.
  std::vector<double> adapt_values;
  // Then the filled values pulled towards a smooth path in time (fill_smoothing.h).
  FillSmoothing smoothing;
  // Last, set: the scope's missing values replaced by their conditional mean under this Gaussian
  // (window_gaussian.h FillFromWindowGaussian).
  std::shared_ptr<const WindowGaussian> gaussian;
  GaussianScope gaussian_scope = GaussianScope::kOneSided;
};
// blend.adapt_values for bucket k (throws std::invalid_argument on another number of values).
double AdaptValues(const ImputationBlend& blend, int bucket);
// Whether any bucket is adapted.
bool AdaptsToMotion(const ImputationBlend& blend);
// f holds one window (f.frames rows); refined: the refiner's output for it, [T, N] metres
// root-relative. Returns the blended [T, N] (observed values as refined holds them).
std::vector<float> BlendRefinerFills(const Skeleton& skeleton, const RefinerFills& f,
                                     const std::vector<float>& refined,
                                     const ImputationBlend& blend);

// Root-relative rows without the root [T, N] (poses, or their mask) as [T, N + 3] rows whose first
// three values, the root's, are 0: positions with the root at the origin (observed, for a mask).
template <typename V>
std::vector<V> WithRootAtOrigin(const V* rows, size_t frames, size_t coords) {
  std::vector<V> out(frames * (coords + 3), V{0});
  for (size_t t = 0; t < frames; ++t)
    std::copy(rows + t * coords, rows + (t + 1) * coords, out.begin() + t * (coords + 3) + 3);
  return out;
}

// Appends `f`'s window to `all` (the same number of frames in each).
void AppendRefinerFills(const RefinerFills& f, RefinerFills* all);

// positions [T, J, 3] (root observed in every frame), missing [T, J, 3]; fallback [J, 3]
// root-relative (the training mean pose).
RefinerFills MakeRefinerFills(const Skeleton& skeleton, const std::vector<float>& positions,
                              const std::vector<uint8_t>& missing,
                              const std::vector<float>& fallback);

}  // namespace motionfork
