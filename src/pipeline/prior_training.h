// `prior train`: a pose prior trained on single frames of a protocol's training split into a
// bundle folder (prior.yaml, weights.npy, train_log.tsv), resumable from its checkpoint.
#pragma once

#include <functional>
#include <string>

#include "core/progress.h"
#include "flow/pose_prior.h"
#include "flow/prior_data.h"
#include "flow/trainer.h"

namespace motionfork::pipeline {

struct PriorTrainingRequest {
  std::string protocol;               // name or YAML path
  std::string data;                   // the protocol's data folder
  std::string out;                    // bundle folder (and checkpoint.pt while training)
  std::string config = "flow_prior";  // model config name or YAML path
  std::string split_file;             // "" = the protocol's
  bool restart = false;               // discard a checkpoint or a trained prior in `out`
  int threads = 1;                    // recorded in the summary (the caller pins them)
  std::string config_dir, cache_dir;
};

struct PriorTrainingCallbacks {
  StageProgress loading;  // the dataset
  // Once the data and the untrained prior are ready.
  std::function<void(const PosePrior&, const PriorData&, const std::string& config_path)> started;
  PriorTrainCallbacks training;  // per step and epoch; stop_requested
};

struct PriorTrainingRun {
  bool completed = false;     // false: stopped; the checkpoint keeps every finished epoch
  std::string checkpoint;     // its path
  PriorTrainOutcome outcome;  // epochs, whether raised, whether the held-out NLL still fell
  PriorTrainingSummary summary;
};

// Throws std::invalid_argument when `out` holds a trained prior and no checkpoint (unless
// restart).
PriorTrainingRun TrainPriorBundle(const PriorTrainingRequest& request,
                                  const PriorTrainingCallbacks& callbacks);

}  // namespace motionfork::pipeline
