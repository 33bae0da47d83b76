// How much of the denoising refiner's correction to keep, by the local size of that correction
// (no LibTorch): where the refiner changes a motion little, the motion was probably clean and the
// change is mostly the refiner's own error; where it changes it a lot, the input was noisy. Each
// frame's correction size (LocalCorrectionCm, refined against the input) falls in one of
// kRefinerBlendBins bins, each with a weight (DvaeManifest::refiner_blend, fitted on held-out
// training clips at the end of `dvae refine`): output = base + weight x (refined - base), the base
// the input where it looks clean and the input smoothed by a Gaussian of `sigma` frames where it
// looks noisy (SmoothWhereNoisy; a light smoothing removes frame-to-frame noise). What is left of
// the noise is mostly frame-to-frame and shows as acceleration: where the input looks noisy the
// output is also smoothed, by a Gaussian of `smooth` frames. A clean input keeps its detail, its
// last frames included (which a forecaster reads).
#pragma once

#include <string>
#include <vector>

namespace motionfork {

constexpr int kRefinerBlendBins = 10;
// Upper edges of the bins but the last, cm per joint.
inline constexpr double kRefinerBlendEdges[kRefinerBlendBins - 1] = {0.25, 0.5, 0.75, 1.0, 1.25,
                                                                     1.5,  2.0, 3.0,  5.0};
int RefinerBlendBin(double correction_cm);
constexpr double kSmoothFromCm = 0.5, kSmoothFullCm = 1.0;
std::string RefinerBlendBinName(int bin);  // "0.75-1 cm"

// Per frame of a motion [T, J, 3], the RMS over the joints and the frames within `half` of it of
// the distance between refined and input, cm.
std::vector<double> LocalCorrectionCm(const std::vector<float>& input,
                                      const std::vector<float>& refined, int joints, int half = 15);

// motion smoothed by a Gaussian of sigma frames where the local correction is large: fully from
// kSmoothFullCm, not at all below kSmoothFromCm, linearly between (correction_cm per frame).
std::vector<float> SmoothWhereNoisy(const std::vector<float>& motion,
                                    const std::vector<double>& correction_cm, int joints,
                                    double sigma);

struct RefinerBlend {
  double sigma = 0;             // frames: the base's Gaussian smoothing of a noisy input
  std::vector<double> weights;  // [kRefinerBlendBins], each in [0, 1]; empty: no blend
  double smooth = 0;            // frames: the output's Gaussian smoothing where noisy
};

// base + weight(bin of the frame) x (refined - base), smoothed; no weights: refined unchanged.
std::vector<float> BlendRefined(const std::vector<float>& input, const std::vector<float>& refined,
                                int joints, const RefinerBlend& blend);

// The least-squares weights per bin for a base of `sigma` frames over several settings (noise
// kinds, clean among them), each setting counted by its number of values: add each setting's
// motions, then Blend().
class RefinerBlendFit {
 public:
  explicit RefinerBlendFit(double sigma = 0);
  // One setting's motions: inputs, the refiner's outputs and the clean motions, [T, J, 3] each.
  void AddSetting(const std::vector<std::vector<float>>& inputs,
                  const std::vector<std::vector<float>>& refined,
                  const std::vector<std::vector<float>>& clean, int joints);
  RefinerBlend Blend() const;  // weights in [0, 1]; 1 where no data
  // The summed mean squared error (m^2) of the settings with Blend()'s weights.
  double Error() const;

 private:
  double sigma_;
  std::vector<double> ee_, ce_, cc_;
};

}  // namespace motionfork
