// Latent codes for the body parts (LibTorch).
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <vector>

namespace motionfork {

// z[p]: [histories * k, nz], standard normal from `gen`; sample b = h * k + i. A fixed part gets
// one latent per history, shared by its k samples (same legs, varied arms).
std::vector<torch::Tensor> SampleLatents(int64_t histories, int64_t k, int64_t nz,
                                         const std::vector<bool>& fixed, at::Generator& gen);

// Training latents, nested as in GSPS: part p draws per_part[p] codes for each combination of the
// earlier parts' codes, so there are prod(per_part) samples per history; sample index is the
// mixed-radix number (i_0, i_1, ...). z[p] depends on (i_0..i_p) only.
std::vector<torch::Tensor> NestedLatents(int64_t histories, const std::vector<int64_t>& per_part,
                                         int64_t nz, at::Generator& gen);

// A CPU random generator seeded with `seed` (futures depend only on it, not on global state).
at::Generator MakeGenerator(uint64_t seed);

}  // namespace motionfork
