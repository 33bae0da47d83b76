// HG-VAE training: negative ELBO with a linear KL warm-up, Adam, gradient-norm clipping, a CSV
// log of every term per epoch, the bundle and a checkpoint after every epoch, resume. No LibTorch
// in this header.
//
// Deterministic for a seed: each epoch's windows and noise come from generators seeded by (seed,
// epoch), so a resumed run continues exactly as an uninterrupted one.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "dataset/dataset.h"
#include "imputation/hgvae_options.h"

namespace motionfork {

// Root-relative poses without the root, per clip [T_c, N] (N = 3 per non-root joint), metres.
struct HgvaeClips {
  std::vector<std::vector<float>> poses;
  std::vector<int> labels;  // class index per clip (-1 = none)
};

struct HgvaeData {
  int coords = 0;
  HgvaeClips train, held_out;        // held_out: a share of the training split's clips
  std::vector<std::string> classes;  // conditional training: the actions, sorted

  // Frames of the training clips (held-out ones not counted).
  long long train_frames() const;
};

// Training split only; held-out clips chosen by the seed. With condition "action" every clip's
// action becomes a class. Clips shorter than `window` frames are left out.
HgvaeData MakeHgvaeData(const Dataset& dataset, const HgvaeTrainOptions& options, int window);

// Every window of every clip (stride 1), at most `limit` spread evenly: [count, window, N].
std::vector<float> HeldOutWindows(const HgvaeClips& clips, int window, int coords, int limit,
                                  std::vector<int>* labels = nullptr);

struct HgvaeEpochLog {
  int epoch = 0;  // 0-based
  double seconds = 0, kl_weight = 0;
  std::vector<std::pair<std::string, double>>
      terms;  // loss, nll, kl, kl0.., held-out elbo, mse, score
};

struct HgvaeTrainCallbacks {
  std::function<void(int epoch, double fraction, double loss, double nll, double kl)> step;
  std::function<void(const HgvaeEpochLog&)> epoch;
  std::function<void(const std::string&)> message;
};

struct HgvaeTrainSummary {
  int first_epoch = 0, epochs_done = 0;
  double seconds = 0;
};

// base: protocol, fps, skeleton, ood_k, impute defaults, info (normalisation, classes, model sizes
// and OoD statistics are filled here). Writes OUT/hgvae.yaml + OUT/hgvae.pt, OUT/log.csv,
// OUT/checkpoint/; resumes from OUT/checkpoint. stop_after_epochs > 0 ends early.
HgvaeTrainSummary TrainHgvae(const HgvaeTrainConfig& config, const HgvaeManifest& base,
                             const HgvaeData& data, const std::string& out_dir,
                             const HgvaeTrainCallbacks& callbacks, int stop_after_epochs = 0);

struct HgvaeRefineCallbacks {
  std::function<void(int epoch, double fraction, double loss)> step;
  std::function<void(const HgvaeEpochLog&)> epoch;
  std::function<void(const std::string&)> message;
};

// hgvae_dir: a trained HG-VAE bundle. Trains the config's `refiner` (supervised: clean training
// windows with random masks, their spline, linear and rigid-limb fills in; the loss: each window's
// log error at the missing values relative to the spline's) and writes OUT: the same bundle with
// the refiner (impute.start refiner, 0 steps) at the epoch with the lowest held-out loss, log.csv
// and checkpoint/ (running again resumes).
HgvaeTrainSummary RefineHgvae(const HgvaeTrainConfig& config, const std::string& hgvae_dir,
                              const HgvaeData& data, const std::string& out_dir,
                              const HgvaeRefineCallbacks& callbacks, int stop_after_epochs = 0);

// Rewrites a trained bundle's settings that do not change its weights from `config`: the
// imputation defaults, the out-of-distribution score and k, and that score's statistics over the
// held-out windows (recomputed). `hgvae train` does this on a run whose epochs are all done.
void RefreshBundleSettings(const std::string& dir, const HgvaeData& data,
                           const HgvaeTrainConfig& config);

}  // namespace motionfork
