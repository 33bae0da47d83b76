// A trained HG-VAE, ready to use (no LibTorch in this header): posterior scores and
// out-of-distribution flags, imputation of missing values, evidence lower bounds, sampling.
//
// Windows are [count, T, N] floats: T = window() frames of N = coords() root-relative coordinates
// without the root (metres; joint j's x, y, z at 3 (j - 1) .. 3 (j - 1) + 2), the layout of
// PoseVectorsWithoutRoot. Missing-value masks have the same layout (1 = missing). Work is done in
// chunks of 64 windows, so any count is fine, shared by up to threads() threads with the same
// results for any number (each chunk has its own seed). Inference only: no call trains the model.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/skeleton.h"
#include "imputation/hgvae_options.h"
#include "imputation/refiner_fills.h"

namespace motionfork {

class HgvaeNet;  // imputation/hgvae_net.h (LibTorch)

struct ImputeResult {
  std::vector<float> windows;        // [count, T, N], observed values unchanged
  std::vector<double> score_before;  // the bundle's OoD score with the missing values at the mean
  std::vector<double> score_after;   // at the chosen step
  std::vector<int> best_step;        // 0 = the mean start was best
};

struct HgvaeWindowFigures {
  std::vector<double> elbo;         // evidence lower bound, nats per window (density in metres)
  std::vector<double> score;        // posterior score (the paper's p(z|x))
  std::vector<double> joint_score;  // posterior score + log p(x | posterior means)
  std::vector<double>
      recon_mse;  // squared error of the reconstruction (posterior means), m^2 per value
  std::vector<double> recon_mse_sampled;       // the same with latents sampled from the posterior
  std::vector<std::vector<double>> kl_levels;  // [level][window], nats
};

class HgvaeModel {
 public:
  // A model over a built network (in eval mode) and the manifest it was built from. Bundles on
  // disk: bundle/hgvae_bundle.h (LoadHgvaeModel).
  static HgvaeModel FromNet(HgvaeManifest manifest, HgvaeNet net);

  const HgvaeManifest& manifest() const;
  const Skeleton& skeleton() const;
  int window() const;  // frames
  int coords() const;  // N
  int64_t num_parameters() const;
  // Threads sharing the chunks of one call (>= 1; default 1). A setting of this copy of the model
  // only. Pin LibTorch's own pool to one thread (PinThreads(1)) when using several.
  void set_threads(int threads);
  int threads() const { return threads_; }
  // Class index of a name, -1 for "" ; throws std::invalid_argument listing the classes.
  int ClassIndex(const std::string& name) const;

  // The bundle's out-of-distribution score per window (manifest().ood_score; higher = more
  // typical). class_index -1 = none.
  std::vector<double> Score(const std::vector<float>& windows, int class_index = -1) const;
  // Either score, whatever the bundle's.
  std::vector<double> Score(const std::vector<float>& windows, ImputeObjective score,
                            int class_index = -1) const;
  double OodThreshold() const;  // score_mean - k * score_std
  bool OutOfDistribution(double score) const { return score < OodThreshold(); }

  // Missing values (mask 1) start at the training mean, or where `start` (laid out as windows,
  // e.g. an interpolation; options.start is not read here) has them, and move by Adam on the
  // objective; each window keeps its best step. Throws std::invalid_argument for a window with
  // every value missing or mismatched sizes.
  ImputeResult Impute(const std::vector<float>& windows, const std::vector<uint8_t>& missing,
                      const ImputeOptions& options, int class_index = -1,
                      const std::vector<float>* start = nullptr) const;
  // The imputation refiner's fill of a whole motion (root-relative [T, N], metres; every value,
  // observed ones included): the spline's values corrected by the refiner, in windows of its
  // length blended, then put together with the spline and the local polynomial as the bundle's
  // calibration says (BlendRefinerFills with refiner_weights, refiner_local_weights and
  // refiner_keep_bones; `calibrated` false: the refiner's output as it is). Throws
  // std::invalid_argument when the bundle has no refiner.
  std::vector<float> Refine(const RefinerFills& fills, bool calibrated = true) const;
  // The calibrated stages after the refiner, as the manifest records them.
  ImputationBlend calibrated_blend() const;
  bool has_refiner() const;

  // Mean imputation (the baseline): missing values -> training mean.
  std::vector<float> MeanImpute(const std::vector<float>& windows,
                                const std::vector<uint8_t>& missing) const;

  // ELBO (one posterior sample per window, chunk c's from ItemSeed(seed, c)), score, reconstruction
  // error, KL per level.
  HgvaeWindowFigures Evaluate(const std::vector<float>& windows, uint64_t seed = 0) const;

  // count windows [count, T, N] from the prior (class_index -1 = no class); sample_latents false
  // takes each level's prior mean.
  std::vector<float> Sample(int count, int class_index, uint64_t seed,
                            bool sample_latents = true) const;

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
  int threads_ = 1;
};

}  // namespace motionfork
