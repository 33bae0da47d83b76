// Generator training as text for people: the progress bar's loss terms in short and the run's
// closing lines (what was trained, where it went, the all-reduce's share with several workers).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "generator/training/training.h"
#include "generator/training/training_setup.h"

namespace motionfork {

// Every loss term in short: "loss 0.43 past 0.0011 limb 0.0002 div0 0.0063 ...".
std::string TrainingTermsText(const std::vector<std::pair<std::string, double>>& terms);

// Before the first epoch: the training windows (cut every `stride` frames), how many have pseudo
// multimodal futures, and where the angle and prior losses come from.
std::string TrainingSetupText(const TrainingWindows& data, int stride,
                              const LossHookSources& losses);

// What a run of `epochs` epochs into `out` did, one line each, newline-terminated.
std::string TrainingDoneText(const TrainSummary& summary, int epochs, const std::string& out);

}  // namespace motionfork
