// HG-VAE training as text for people: what it trains on and what a run did.
#pragma once

#include <string>

#include "imputation/training/hgvae_training.h"

namespace motionfork {

// "HG-VAE: windows of W frames x C coordinates; N training clips (F frames), M held out...".
std::string HgvaeDataText(const HgvaeData& data, int window);

// What a run of `config` into `out` did (trained epochs, or that all were trained already and
// the bundle's settings were refreshed), newline-terminated.
std::string HgvaeTrainingDoneText(const HgvaeTrainSummary& summary, const HgvaeTrainConfig& config,
                                  const std::string& out);

// After `hgvae refine`: the epochs trained and the bundle written.
std::string HgvaeRefineDoneText(const HgvaeTrainSummary& s, const std::string& out);

}  // namespace motionfork
