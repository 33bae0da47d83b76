// `motionfork train` as one library call, from a model config to a bundle: the config read and its
// overrides applied, the recipe recorded (OUT/training.yaml), a prior the config names and that is
// not there yet trained first (by the caller's hook: prior training lives in pipeline/), the data
// and its pseudo multimodal futures, the loss terms, the generator's epochs and, when the config
// has a `trajectory` section, the trajectory network once the generator's last epoch is done.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "core/progress.h"
#include "generator/kernels/precision.h"
#include "generator/training/training.h"

namespace motionfork {

struct GeneratorTrainingRequest {
  std::string config_path;             // resolved (config/config_paths.h)
  std::string data, split_file, out;   // split_file "" = the protocol's
  int epochs = 0;                      // > 0: replaces the config's (OverrideEpochs)
  int stop_after = 0;                  // > 0: stop after this many epochs of this run
  std::optional<Precision> precision;  // replaces the config's training.precision
  std::string config_dir, cache_dir;
};

struct GeneratorTrainingHooks {
  // Trains the prior bundle the config names, into `out`, on the same data and split; returns
  // false when that run stopped (Ctrl-C), which ends this one. Required when the config names a
  // prior that does not exist.
  std::function<bool(const std::string& protocol, const std::string& out, int threads)> train_prior;
  StageProgress progress;                        // loading, pseudo multimodal futures
  std::function<void(const std::string&)> text;  // report lines, newline-terminated
  // The per-step and per-epoch reports of a loop of `epochs` epochs (the generator's, then the
  // trajectory network's).
  std::function<TrainCallbacks(int epochs)> epochs;
};

// Returns false when the prior's training stopped before the generator's began.
bool RunGeneratorTraining(const GeneratorTrainingRequest& request,
                          const GeneratorTrainingHooks& hooks);

}  // namespace motionfork
