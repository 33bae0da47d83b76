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
// Whether epoch `epoch` (0-based) of `epochs` gets a line: every epoch of a run of up to
// kPriorEpochLines epochs; of a longer one (a small dataset's raised schedule: 1,500 epochs of one
// step), the first, the last and every n-th, so that about kPriorEpochLines lines remain.
constexpr int kPriorEpochLines = 100;
bool PriorEpochGetsLine(int epoch, int epochs);
// The figures of a completed run, where its bundle is (`out`), and a warning when the held-out
// NLL was still falling at the end.
std::string PriorTrainingDoneText(const PriorTrainingRun& run, const std::string& out);
// A run stopped by Ctrl-C: the checkpoint in `out` keeps what it finished.
std::string PriorTrainingInterruptedText(const std::string& out);

}  // namespace motionfork::pipeline
