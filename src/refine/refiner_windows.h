// A refiner over a sequence of any length (LibTorch): windows of `window` frames every `stride`
// frames (the last one ends at the last frame), each corrected on its own, the corrections blended
// where windows overlap with weights min(i + 1, length - i) (a window's edges count least). A
// sequence shorter than a window is one window of its own length.
#pragma once

#include <torch/torch.h>

#include "refine/refiner_net.h"

namespace motionfork {

// input [T, in] -> correction [T, out]; windows go through the net in batches of 256.
torch::Tensor RefineInWindows(TemporalRefiner& net, const torch::Tensor& input, int window,
                              int stride);

}  // namespace motionfork
