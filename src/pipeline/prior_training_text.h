// A pose prior's training run (prior_training.h) as text for people: what `motionfork prior train`
// prints before, during and after it.
#pragma once

#include <string>

#include "pipeline/prior_training.h"

namespace motionfork::pipeline {

// Once the data and the untrained prior are ready: the model, the data and the training settings.
std::string PriorTrainingStartText(const PosePrior& prior, const PriorData& data,
                                   const std::string& config_path, const PriorTrainingRequest& o);
// A finished epoch's line: learning rate, train and held-out NLL, time.
std::string PriorEpochText(const PriorTrainProgress& p);
// The figures of a completed run and where its bundle is (`out`).
std::string PriorTrainingDoneText(const PriorTrainingSummary& y, const std::string& out);
// A run stopped by Ctrl-C: the checkpoint in `out` keeps what it finished.
std::string PriorTrainingInterruptedText(const std::string& out);

}  // namespace motionfork::pipeline
