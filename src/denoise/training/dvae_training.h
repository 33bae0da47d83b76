// Motion-DVAE training (no LibTorch in this header):
// - TrainDvae: the motion prior on clean windows (ELBO with KL annealing, bone-length term).
// - RefineDvae: the supervised denoising refiner (refine/refiner_net.h) of a bundle.
// - FinetuneDvae: unsupervised denoising training ("regression mode"): windows of the training
//   split corrupted by the config's noise kinds; only the encoder, the initial-state predictor
//   and the noise predictor learn; no clean target enters the loss (clean windows are used only
//   to report the held-out error in the log).
// Both write a CSV log per epoch, a checkpoint per epoch (running again resumes) and a bundle.
// Deterministic for a seed: epoch e's windows and noise come from generators seeded by (seed, e).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "dataset/dataset.h"
#include "denoise/dvae_options.h"

namespace motionfork {

struct DvaeData {
  int joints = 0;
  std::vector<std::vector<float>> train, held_out;  // per clip [T, J, 3], metres

  // Frames of the training clips (held-out ones not counted).
  long long train_frames() const;
};

// The training split's clips of >= window frames; a share of them (chosen by the seed) held out.
DvaeData MakeDvaeData(const Dataset& dataset, double held_out_share, uint64_t seed, int window);

struct DvaeEpochLog {
  int epoch = 0;  // 0-based
  double seconds = 0, kl_weight = 0;
  std::vector<std::pair<std::string, double>> terms;
};

struct DvaeTrainCallbacks {
  std::function<void(int epoch, double fraction, double loss)> step;
  std::function<void(const DvaeEpochLog&)> epoch;
  std::function<void(const std::string&)> message;
};

struct DvaeTrainSummary {
  int first_epoch = 0, epochs_done = 0;
  double seconds = 0;
  bool stopped_early = false;
  RefinerBlend refiner_blend;  // RefineDvae: the kept refiner's blend
  bool blend_only = false;     // RefitRefinerBlend: no epoch trained, the blend fitted again
};

// base: protocol, fps, skeleton, noise prior, denoise defaults, info. Writes OUT/dvae.yaml +
// OUT/dvae.pt, OUT/log.csv, OUT/checkpoint/.
DvaeTrainSummary TrainDvae(const DvaeTrainConfig& config, const DvaeManifest& base,
                           const DvaeData& data, const std::string& out_dir,
                           const DvaeTrainCallbacks& callbacks, int stop_after_epochs = 0);

// prior_dir: a bundle from TrainDvae. OUT gets the fine-tuned bundle (the epoch with the lowest
// held-out loss), log.csv and checkpoint/.
DvaeTrainSummary FinetuneDvae(const DvaeTrainConfig& config, const std::string& prior_dir,
                              const DvaeData& data, const std::string& out_dir,
                              const DvaeTrainCallbacks& callbacks, int stop_after_epochs = 0);

// dvae_dir: a fine-tuned (or any) Motion-DVAE bundle. Trains the config's `refiner` (supervised:
// clean training windows corrupted at random levels, the clean window the target) and writes OUT:
// the same bundle with the refiner (denoise.mode refiner) at the epoch with the lowest held-out
// error, log.csv and checkpoint/ (running again resumes).
DvaeTrainSummary RefineDvae(const DvaeTrainConfig& config, const std::string& dvae_dir,
                            const DvaeData& data, const std::string& out_dir,
                            const DvaeTrainCallbacks& callbacks, int stop_after_epochs = 0);

// dvae_dir: a bundle with a refiner, kept as it is: its blend and outlier repair fitted again on
// the data's held-out clips (as at the end of RefineDvae; the config's refiner seed draws the
// noise), the bundle written to OUT (the same weights; OUT may be dvae_dir).
DvaeTrainSummary RefitRefinerBlend(const DvaeTrainConfig& config, const std::string& dvae_dir,
                                   const DvaeData& data, const std::string& out_dir);

}  // namespace motionfork
