// Generator training (LibTorch): Adam with a constant-then-linear learning rate, gradient-norm
// clipping, nested samples per part, every loss term logged per epoch (CSV), a checkpoint and a
// usable bundle after every epoch, resume after interruption. Deterministic for a seed: each
// epoch's windows and latents come from generators seeded by (seed, epoch), so a resumed run
// continues exactly as an uninterrupted one.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "generator/model/generator_options.h"
#include "generator/model/training_options.h"
#include "generator/training/losses.h"
#include "generator/training/training_data.h"

namespace motionfork {

struct TrainCallbacks {
  // After every step: epoch (0-based), fraction of the epoch done, running mean of each term.
  std::function<void(int epoch, double fraction,
                     const std::vector<std::pair<std::string, double>>&)>
      step;
  // After every epoch: its mean terms and wall time.
  std::function<void(int epoch, const std::vector<std::pair<std::string, double>>&, double seconds)>
      epoch;
  std::function<void(const std::string&)> message;
};

struct TrainSummary {
  int first_epoch = 0;  // > 0 when resumed
  int epochs_done =
      0;  // epochs the folder holds at the end (all of them when a finished run resumes)
  double seconds = 0;
  int workers = 1;            // processes in the run (data_parallel.h)
  double reduce_seconds = 0;  // of `seconds`, in the gradient all-reduce (several workers)
  double sync_seconds = 0;    // of `seconds`, in the batch-norm sums (synchronised batch norm)
  int64_t sync_calls = 0;
  int64_t steps = 0;       // optimiser steps of this run
  double gradient_mb = 0;  // gradients all-reduced a step, MB
};

// model: protocol, skeleton and generator sizes (from the train config and the protocol). Writes
// OUT/model.yaml + OUT/generator.pt (the bundle), OUT/log.csv, OUT/checkpoint/. Resumes from
// OUT/checkpoint when it exists. stop_after_epochs > 0 ends early (tests, time budgets).
TrainSummary TrainGenerator(const GeneratorTrainConfig& config, const ModelConfig& model,
                            const TrainingWindows& data, const std::string& out_dir,
                            const LossHooks& hooks, const TrainCallbacks& callbacks,
                            int stop_after_epochs = 0);

// Re-targets a future [t_pred, N, 3] to the bone lengths of `reference` [N, 3], keeping its limb
// directions (root-relative poses, root at the origin; node_parents -1 = root). Output [t_pred, N,
// 3].
void RetargetFuture(const float* future, const float* reference,
                    const std::vector<int64_t>& node_parents, int frames, int nodes, float* out);

}  // namespace motionfork
