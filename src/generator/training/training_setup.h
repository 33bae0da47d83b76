// What `motionfork train` sets up around TrainGenerator: the recipe recorded with the weights
// (OUT/training.yaml) and the loss terms from other modules (angle ranges, pose prior).
#pragma once

#include <memory>
#include <string>

#include "core/skeleton.h"
#include "generator/model/training_options.h"
#include "generator/training/losses.h"

namespace motionfork {

// The split a run trains on, as recorded: the split file's absolute path, or the protocol's own.
std::string TrainingSplitName(const std::string& split_file);

// `--epochs N`: the run's length replaced and its constant learning-rate phase scaled with it (the
// same share of the run, rounded), so that a shortened or lengthened recipe still ends by decaying
// to 0 (120 epochs with 60 constant, cut to 40: 20 constant, then 20 decaying).
void OverrideEpochs(TrainingOptions* training, int epochs);

// OUT/training.yaml holds a header (the config's path, the split, what an --epochs override
// changed; epochs 0 = none) and the config file as read. A folder that has trained epochs is
// refused (FormatError) for another config or split: resuming would mix two recipes in one model.
// A config that differs only in its `trajectory` section is the same recipe (that section trains
// after the generator's last epoch: adding one to a finished run's config trains it).
// Call before any data is read.
// precision: what `--precision` replaced training.precision with ("" = not given).
void RecordTrainingConfig(const std::string& out, const std::string& config_path,
                          const std::string& split_file, int epochs,
                          const std::string& precision = "");

// The folder of the prior bundle a config names: as given (relative to the working folder), else
// relative to the source tree's root (config_dir's parent) when that exists.
std::string FindPriorBundle(const std::string& prior, const std::string& config_dir);
// Whether that folder holds a trained prior (prior.yaml).
bool PriorBundleExists(const std::string& prior, const std::string& config_dir);

// The angle-range and prior loss terms the config names, and what they read (copied into the
// bundle: it describes itself). Relative prior paths are taken from the source tree's root
// (config_dir/..) when they do not exist from the working directory.
struct LossHookSources {
  LossHooks hooks;
  std::string constraints_path;  // "" = no angle loss
  int constraints = 0;           // angles
  std::string prior_dir;         // "" = no prior loss
};
LossHookSources MakeLossHooks(const GeneratorTrainConfig& config, const Skeleton& skeleton,
                              const std::string& config_dir);

}  // namespace motionfork
