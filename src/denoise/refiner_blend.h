// How much of the denoising refiner's correction to keep, by how rough the input looks (no
// LibTorch): a clean motion is smooth from frame to frame, a noisy one is not, so each frame's
// roughness (InputRoughnessCm: the input's local distance from its own light smoothing; clean
// motion capture ~0.1-0.3 cm, 1 cm of Gaussian noise ~1.2 cm) tells how much the refiner's change
// is noise removed and how much its own error. It works on a few frames as well as on long clips
// (the refiner's own correction of a short clean history is not small). Each frame falls in one of
// kRefinerBlendBins bins of roughness, each with a weight (DvaeManifest::refiner_blend, fitted on
// held-out training clips at the end of `dvae refine`): output = base + weight x (refined - base),
// the base the input where it looks clean and the input smoothed by a Gaussian of `sigma` frames
// where it looks noisy (SmoothWhereNoisy). What is left of the noise is mostly frame-to-frame and
// shows as acceleration: where the input looks noisy the output is also smoothed, by a Gaussian of
// `smooth` frames. A clean input keeps its detail, its last frames included (which a forecaster
// reads).
#pragma once

#include <string>
#include <vector>

#include "denoise/outlier_repair.h"

namespace motionfork {

constexpr int kRefinerBlendBins = 10;
// Upper edges of the bins of roughness but the last, cm per joint.
inline constexpr double kRefinerBlendEdges[kRefinerBlendBins - 1] = {0.25, 0.5, 0.75, 1.0, 1.25,
                                                                     1.5,  2.0, 3.0,  5.0};
int RefinerBlendBin(double roughness_cm);
constexpr double kSmoothFromCm = 0.5, kSmoothFullCm = 1.0;
std::string RefinerBlendBinName(int bin);  // "0.75-1 cm"

// Per frame of a motion [T, J, 3], the RMS over the joints and the frames within `half` of it of
// the distance between refined and input, cm.
// median_over_joints: each frame's squared distance the median over the joints instead of the mean.
std::vector<double> LocalCorrectionCm(const std::vector<float>& input,
                                      const std::vector<float>& refined, int joints, int half = 15,
                                      bool median_over_joints = false);

// What the roughness of a motion is measured against: itself smoothed by a Gaussian of 1 frame
// (the first bundles'), or by a Savitzky-Golay fit of order 3 over 7 frames, which follows fast
// smooth motion (a turning hand) where the Gaussian cuts corners, so that fast clean motion does
// not look rough; on white noise both leave about three quarters of it.
// kSavitzkyGolayMedian: against the Savitzky-Golay fit, each frame's distance the median over
// the joints instead of their RMS, so that outliers left by the repair (a joint here and there)
// do not make a motion look rough everywhere around them and get it smoothed, which spreads each
// outlier's error over its neighbours.
enum class Roughness { kGaussian, kSavitzkyGolay, kSavitzkyGolayMedian };
// "gaussian", "savitzky-golay", "savitzky-golay-median"; RoughnessNamed throws
// std::invalid_argument naming the choices for another name.
std::string RoughnessName(Roughness kind);
Roughness RoughnessNamed(const std::string& name);

// Per frame of a motion [T, J, 3], LocalCorrectionCm between it and its smoothing of `kind`: how
// rough it is around that frame, cm.
std::vector<double> InputRoughnessCm(const std::vector<float>& input, int joints, int half = 15,
                                     Roughness kind = Roughness::kGaussian);

// motion smoothed by a Gaussian of sigma frames where it looks noisy: fully from a roughness of
// kSmoothFullCm, not at all below kSmoothFromCm, linearly between (roughness_cm per frame).
std::vector<float> SmoothWhereNoisy(const std::vector<float>& motion,
                                    const std::vector<double>& roughness_cm, int joints,
                                    double sigma);

// The output smoothings (Gaussian sigmas, frames) an adaptive blend chooses from, and the
// smoothing of the reference it compares with.
inline constexpr double kOutputSmoothings[] = {0.0, 0.5, 0.75, 1.0, 1.5, 2.0};
constexpr double kAccelReferenceSigma = 2.0;

struct RefinerBlend {
  double sigma = 0;             // frames: the base's Gaussian smoothing of a noisy input
  std::vector<double> weights;  // [kRefinerBlendBins], each in [0, 1]; empty: no blend
  double smooth = 0;            // frames: the output's Gaussian smoothing where noisy
  // > 0: the output's smoothing where noisy chosen for each motion instead of `smooth`
  // (SmoothToAcceleration), so that slow motion, whose clean accelerations are small beside what
  // is left of the noise, is smoothed more than fast motion
  double accel_bound = 0;
  OutlierRepair outliers;  // of the input, before the refiner reads it (DvaeModel::Denoise)
  Roughness roughness = Roughness::kGaussian;  // what the bins and the smoothing are keyed on
};

// SmoothWhereNoisy with the least of kOutputSmoothings whose result's mean acceleration is at most
// `bound` times that of the motion smoothed everywhere by kAccelReferenceSigma frames (an estimate
// of the clean motion's, low for fast motion); the largest where none is.
std::vector<float> SmoothToAcceleration(const std::vector<float>& motion,
                                        const std::vector<double>& roughness_cm, int joints,
                                        double bound);

// base + weight(roughness bin of the frame) x (refined - base), smoothed where rough; no weights:
// refined unchanged.
std::vector<float> BlendRefined(const std::vector<float>& input, const std::vector<float>& refined,
                                int joints, const RefinerBlend& blend);

// The least-squares weights per bin for a base of `sigma` frames over several settings (noise
// kinds, clean among them), each setting counted by its number of values: add each setting's
// motions, then Blend().
class RefinerBlendFit {
 public:
  explicit RefinerBlendFit(double sigma = 0, Roughness roughness = Roughness::kGaussian);
  // One setting's motions: inputs, the refiner's outputs and the clean motions, [T, J, 3] each.
  void AddSetting(const std::vector<std::vector<float>>& inputs,
                  const std::vector<std::vector<float>>& refined,
                  const std::vector<std::vector<float>>& clean, int joints);
  RefinerBlend Blend() const;  // weights in [0, 1]; 1 where no data
  // The summed mean squared error (m^2) of the settings with Blend()'s weights.
  double Error() const;

 private:
  double sigma_;
  Roughness roughness_;
  std::vector<double> ee_, ce_, cc_;
};

}  // namespace motionfork
