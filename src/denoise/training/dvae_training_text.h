// What `motionfork dvae train / finetune / refine` print around a training run, for people.
#pragma once

#include <string>

#include "denoise/training/dvae_training.h"

namespace motionfork {

// The three Motion-DVAE training stages, in the order they run.
enum class DvaeStage { kPrior, kFinetune, kRefiner };

// The data and what the stage trains, before the run.
std::string DvaeTrainingStartText(DvaeStage stage, const DvaeTrainConfig& config,
                                  const DvaeData& data);
// The epochs trained, the bundle written and the next step.
std::string DvaeTrainingDoneText(DvaeStage stage, const DvaeTrainSummary& s,
                                 const std::string& out);

}  // namespace motionfork
