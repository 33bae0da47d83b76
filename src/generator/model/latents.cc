#include "generator/model/latents.h"

#include <ATen/CPUGeneratorImpl.h>

#include <stdexcept>
#include <string>

namespace motionfork {

at::Generator MakeGenerator(uint64_t seed) { return at::detail::createCPUGenerator(seed); }

std::vector<torch::Tensor> SampleLatents(int64_t histories, int64_t k, int64_t nz,
                                         const std::vector<bool>& fixed, at::Generator& gen) {
  if (histories < 1 || k < 1) {
    throw std::invalid_argument("SampleLatents: expected >= 1 history and >= 1 sample, got " +
                                std::to_string(histories) + " and " + std::to_string(k));
  }
  std::vector<torch::Tensor> z;
  for (bool f : fixed) {
    if (f) {
      z.push_back(torch::randn({histories, 1, nz}, gen)
                      .expand({histories, k, nz})
                      .reshape({histories * k, nz}));
    } else {
      z.push_back(torch::randn({histories * k, nz}, gen));
    }
  }
  return z;
}

std::vector<torch::Tensor> NestedLatents(int64_t histories, const std::vector<int64_t>& per_part,
                                         int64_t nz, at::Generator& gen) {
  int64_t total = 1;
  for (int64_t n : per_part) total *= n;
  std::vector<torch::Tensor> z;
  int64_t before = 1;  // combinations of earlier parts
  for (int64_t n : per_part) {
    const int64_t after = total / (before * n);  // samples of later parts per code
    const torch::Tensor codes = torch::randn({histories, before * n, 1, nz}, gen);
    z.push_back(codes.expand({histories, before * n, after, nz}).reshape({histories * total, nz}));
    before *= n;
  }
  return z;
}

}  // namespace motionfork
