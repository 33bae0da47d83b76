// Pairwise L1 distances between the predicted futures of sample groups, on some nodes and frames:
// what GSPS's diversity term measures (pdist with p = 1). One autograd function that reads the
// predictions in place; as LibTorch ops (index_select of the rows, of the nodes, cdist and their
// backward passes) the diversity terms took about a tenth of a training step.
#pragma once

#include <torch/torch.h>

#include <vector>

namespace motionfork {

// pred [B, T, N, 3] (contiguous float, differentiable); rows [G, n] int64: sample indices, each
// group's n samples; a sample may appear in one group only. Distances sum |pred[a] - pred[b]| over
// frames t_from..T-1, the given nodes and the three axes. Returns [G, n, n] (symmetric, zero
// diagonal). The gradient's sign of a zero difference is zero (as LibTorch's cdist).
torch::Tensor GroupL1Distances(const torch::Tensor& pred, const torch::Tensor& rows,
                               const std::vector<int64_t>& nodes, int64_t t_from);

}  // namespace motionfork
