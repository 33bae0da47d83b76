// Fixture: a tiny Motion-DVAE trained in code on synthetic walks of the test humanoid (Bandai
// joint names and order): prior and fine-tuned denoiser, for the denoise module's tests and the
// commands'.
#pragma once

#include <string>

#include "denoise/dvae_options.h"
#include "denoise/training/dvae_training.h"

namespace motionfork::testing {

// Training and held-out clips: walks of the test humanoid with different seeds, 30 Hz.
DvaeData TinyDvaeData(int clips = 8, int frames = 60);

// A small config: window 10, hidden 32, latent 8, MLPs of 32 with 8 groups.
DvaeTrainConfig TinyDvaeConfig(int epochs, int finetune_epochs);

DvaeManifest TinyDvaeBase(const DvaeTrainConfig& config);

// Trains the prior into dir/prior and fine-tunes it into dir/denoiser.
void WriteTinyDvaeBundles(const std::string& dir, int epochs = 3, int finetune_epochs = 2);

}  // namespace motionfork::testing
