// The HG-VAE's figures on a set of windows (no LibTorch, no printing): imputation error against
// mean imputation under simulated occlusion, and how well the posterior score separates clean
// windows from degraded or impossible ones (AUROC).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "imputation/hgvae_model.h"

namespace motionfork {

// One occlusion setting: random values (share > 0) or whole joints over the window.
struct Occlusion {
  std::string name;         // "random 10%", "left arm", ...
  double share = 0;         // random: share of values; 0 for joints
  std::vector<int> joints;  // skeleton joint indices (non-root)
};

struct ImputationFigure {
  Occlusion occlusion;
  int64_t missing_values = 0;
  double mse_mean = 0;                       // mean imputation, m^2 per missing value
  double mse_model = 0;                      // HG-VAE imputation
  double reduction = 0;                      // 1 - mse_model / mse_mean
  double score_before = 0, score_after = 0;  // mean posterior score (mean-filled, imputed)
};

// windows [count, T, N]. Each setting's mask is drawn from `seed` (the same for every model).
// progress(done, total) after each setting.
std::vector<ImputationFigure> ImputationExperiment(
    const HgvaeModel& model, const std::vector<float>& windows,
    const std::vector<Occlusion>& settings, const ImputeOptions& options, uint64_t seed,
    const std::function<void(int, int)>& progress = nullptr);

// Area under the ROC curve of "a is more typical than b" (ties count one half): the probability
// that a random clean score exceeds a random degraded one.
double Auroc(const std::vector<double>& clean, const std::vector<double>& degraded);

// Degradations for out-of-distribution tests, windows [count, T, N] -> same layout.
// A share of values replaced by the model's training mean.
std::vector<float> ReplaceWithMean(const HgvaeModel& model, const std::vector<float>& windows,
                                   double share, uint64_t seed);
// Impossible bodies: every bone scaled by `factor` (root-relative, through the skeleton's parents).
std::vector<float> ScaleBones(const Skeleton& skeleton, const std::vector<float>& windows,
                              float factor);
// Impossible motion: each frame replaced by a frame of another random window (teleporting poses).
std::vector<float> ShuffleFrames(const std::vector<float>& windows, int coords, uint64_t seed);

// The standard occlusion settings of the issue: random 1%, 10%, 50%, 90% of values, and each
// whole limb (arms, legs below the hip or shoulder) over the window, by the skeleton's names
// when it has them.
std::vector<Occlusion> StandardOcclusions(const Skeleton& skeleton);

}  // namespace motionfork
