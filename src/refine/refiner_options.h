// Settings of a temporal refiner (refine/refiner_net.h): plain structs, no LibTorch. A bundle's
// manifest holds them under `refiner:`; channels 0 means the bundle has none.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace motionfork {

struct RefinerOptions {
  int channels = 0;  // width of every convolution; 0: no refiner
  int window = 64;   // frames per window (longer motions are cut and blended, stride below)
  int stride = 16;   // windows start every `stride` frames
  std::vector<int> dilations = {1, 2, 4, 8, 1, 2, 4, 8};  // one residual block each (kernel 3)
  int linear_reach = 7;  // the linear path's frames on each side (refine/refiner_net.h)
  // The linear path starts as a Gaussian smoother (denoising) or at zero (imputation: the
  // interpolation it corrects is right where the gaps are short).
  bool smooth_start = true;
  bool enabled() const { return channels > 0; }
  // Frames on each side that reach an output frame: the larger of linear_reach and
  // 1 (input conv) + sum(dilations).
  int reach() const;
};

// Training a refiner: supervised, corrupted clean windows in, the clean window the target.
struct RefinerTrainOptions {
  int epochs = 30;
  int windows_per_epoch = 10000;
  int batch_size = 32;
  double learning_rate = 1e-3;  // Adam
  double lr_decay = 0.93;       // learning rate x this after every epoch
  double grad_clip = 10;
  int patience = 8;  // stop when the held-out error has not improved for this many epochs
  uint64_t seed = 3;
  int threads = 1;
};

// Throws std::invalid_argument naming the field and the rule it broke (`what`: "refiner").
void ValidateRefinerOptions(const RefinerOptions& o, const std::string& what);

}  // namespace motionfork
