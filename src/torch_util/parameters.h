// How many numbers a LibTorch module learns (every registered parameter, frozen ones included), and
// weights copied between modules by name.
#pragma once

#include <torch/torch.h>

#include <cstdint>

namespace motionfork {

inline int64_t CountParameters(const torch::nn::Module& module) {
  int64_t n = 0;
  for (const torch::Tensor& p : module.parameters()) n += p.numel();
  return n;
}

// Copies every parameter and buffer of `from` into the tensor of the same name in `to` (a larger
// network that holds it, e.g. one with a refiner added); names `to` alone has keep their values.
inline void CopyTensorsByName(const torch::nn::Module& from, torch::nn::Module& to) {
  torch::NoGradGuard no_grad;
  const auto params = from.named_parameters(), buffers = from.named_buffers();
  for (auto& p : to.named_parameters())
    if (params.contains(p.key())) p.value().copy_(params[p.key()]);
  for (auto& b : to.named_buffers())
    if (buffers.contains(b.key())) b.value().copy_(buffers[b.key()]);
}

}  // namespace motionfork
