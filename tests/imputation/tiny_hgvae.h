// Fixture: a tiny HG-VAE trained in code on synthetic walks of the test humanoid (Bandai joint
// names and order), so imputation, scores and the commands can be tested anywhere in seconds.
#pragma once

#include <string>

#include "imputation/hgvae_options.h"
#include "imputation/training/hgvae_training.h"

namespace motionfork::testing {

// Training and held-out clips: walks of the test humanoid with different seeds, 30 Hz.
HgvaeData TinyHgvaeData(int clips = 12, int frames = 60);

// A small config: levels 1x16, 8x16, full graph x 16; width 32; window `window` frames.
HgvaeTrainConfig TinyHgvaeConfig(int window, int epochs);

// Trains TinyHgvaeConfig on TinyHgvaeData and writes the bundle to dir (hgvae.yaml, hgvae.pt).
void WriteTinyHgvaeBundle(const std::string& dir, int window = 5, int epochs = 6);

}  // namespace motionfork::testing
