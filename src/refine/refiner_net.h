// The temporal refiner (LibTorch): a correction of a motion window from the window itself.
//
//   correction [B, T, out] = linear(x) + conv1x1(relu(h)), where
//   linear: a learned linear filter of each of the first `out` input values over
//           `linear_reach` frames each side, starting as a Gaussian smoother (the classical tool:
//           the refiner starts where it is and learns what it cannot do);
//   h: conv(k 3) of x, then residual blocks h + conv1x1(relu(conv_k3,dilation d(relu(h)))).
//
// Convolutions run over time with replicated edges, so any T >= 1 works; the network's output layer
// starts at zero. No normalisation layer: training and use compute the same function.
#pragma once

#include <torch/torch.h>

#include <vector>

#include "refine/refiner_options.h"

namespace motionfork {

class TemporalRefinerImpl : public torch::nn::Module {
 public:
  TemporalRefinerImpl(const RefinerOptions& options, int64_t in, int64_t out);
  torch::Tensor forward(const torch::Tensor& x);  // [B, T, in] -> [B, T, out]

 private:
  torch::nn::Conv1d linear{nullptr}, input{nullptr}, output{nullptr};
  std::vector<torch::nn::Conv1d> dilated, mix;
};
TORCH_MODULE(TemporalRefiner);

}  // namespace motionfork
