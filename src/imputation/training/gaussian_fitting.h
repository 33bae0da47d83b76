// Fitting the imputation's last stage, a Gaussian over windows of frames (window_gaussian.h), to
// an HG-VAE bundle: the Gaussian over windows of the model's length is fitted on the training
// clips the HG-VAE trained on, then measured on histories of the held-out ones (random shares
// missing, filled over the history alone as `predict --impute` does) against the bundle's own fill
// (the calibrated refiner and its smoothing), once for each scope: the values observed on one side
// only, and every value of the history. The scope of lowest summed relative squares over all
// missing values is taken when it beats the bundle's fill. No test clip is read.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/progress.h"
#include "imputation/hgvae_model.h"
#include "imputation/window_gaussian.h"

namespace motionfork {

constexpr GaussianScope kGaussianScopes[] = {GaussianScope::kOneSided,
                                             GaussianScope::kShortMotions};

struct GaussianFit {
  WindowGaussian gaussian;
  int training_clips = 0, held_out_clips = 0, histories = 0;  // histories per share
  struct Share {
    double share = 0;
    long long values = 0, one_sided = 0, last = 0;  // missing; one-sided; in the last frame
    // RMS (cm) over all missing values, the one-sided ones and the last frame's: the bundle's fill,
    // then each scope of kGaussianScopes.
    double all_cm[3] = {0, 0, 0}, one_sided_cm[3] = {0, 0, 0}, last_cm[3] = {0, 0, 0};
  };
  std::vector<Share> shares;
  double score[2] = {0, 0};  // per scope: sum over shares of its squares / the bundle fill's
  bool chosen = false;       // the lower score is below the number of shares
  GaussianScope scope = GaussianScope::kOneSided;  // the lower score's
};

// train, held_out: root-relative poses without the root [T, N] on the model's skeleton.
GaussianFit FitGaussian(const HgvaeModel& model, const std::vector<std::vector<float>>& train,
                        const std::vector<std::vector<float>>& held_out, uint64_t seed,
                        const StageProgress& progress = nullptr);

// FitGaussian on the bundle in model_dir, then the bundle written to out_dir (not model_dir), with
// the Gaussian as its refiner_gaussian stage when chosen (as it was otherwise).
GaussianFit FitGaussianIntoBundle(const std::string& model_dir,
                                  const std::vector<std::vector<float>>& train,
                                  const std::vector<std::vector<float>>& held_out, uint64_t seed,
                                  const std::string& out_dir,
                                  const StageProgress& progress = nullptr);

std::string GaussianFitText(const GaussianFit& fit, const std::string& out);

}  // namespace motionfork
