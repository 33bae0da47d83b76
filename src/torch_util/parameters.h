// How many numbers a LibTorch module learns (every registered parameter, frozen ones included).
#pragma once

#include <torch/torch.h>

#include <cstdint>

namespace motionfork {

inline int64_t CountParameters(const torch::nn::Module& module) {
  int64_t n = 0;
  for (const torch::Tensor& p : module.parameters()) n += p.numel();
  return n;
}

}  // namespace motionfork
