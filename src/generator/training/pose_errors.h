// The per-sample error sums of the GSPS losses that touch every predicted frame, in one pass over
// the predictions forward and one backward (a LibTorch autograd function). As separate LibTorch
// ops (slices, differences, squares, norms, sums) these made about twenty passes over the
// [Bh, K, T, N, 3] predictions and their gradient (38 MB at the sizes), most of the
// training step's loss time.
#pragma once

#include <torch/torch.h>

#include <vector>

namespace motionfork {

struct PoseErrors {
  torch::Tensor
      past;  // [Bh, K]: sum over nodes and axes of (pred - truth)^2, mean over past frames
  torch::Tensor future;       // [Bh, K]: the same summed over the future frames
  torch::Tensor future_norm;  // [Bh, K]: sum over future frames, nodes, axes of pred^2
  torch::Tensor limb;  // [Bh, K, T]: sum over bones of (|bone| - truth's |bone| at t_his - 1)^2
};

// pred [Bh, K, T, N, 3] (differentiable), truth [Bh, T, N, 3] (constant); node_parents[n]: the
// parent node of node n, -1 when its parent is the root (the bone then runs from the origin).
// Every output is differentiable in pred.
PoseErrors ComputePoseErrors(const torch::Tensor& pred, const torch::Tensor& truth, int64_t t_his,
                             const std::vector<int64_t>& node_parents);

}  // namespace motionfork
