// Fused graph-layer activations with hand-written backward passes (LibTorch autograd functions).
//
// The generator's hidden layers end in batch norm + tanh on [N, B, H] tensors: as separate
// LibTorch ops that is about eight passes over memory forward and more backward, which costs
// more than the layer's matrix products. These do it in one pass each way.
#pragma once

#include <torch/torch.h>

#include <functional>
#include <vector>

namespace motionfork {

// Synchronised batch norm in a data-parallel run: batch statistics over every worker's share of
// the batch, so that W workers take the step one worker takes on the whole batch.
struct BatchSync {
  // Replaces each value by its sum over the workers (every worker calls it in the same order).
  std::function<void(std::vector<double>*)> sum;
  // This worker's share of the loss: its items / the whole batch's (the weight its gradients get
  // when they are summed over the workers).
  double share = 1;
};

// tanh(x) by kernels::Tanh (kernels/tanh.h), x any contiguous float tensor; differentiable.
torch::Tensor FusedTanh(const torch::Tensor& x);

// Training-mode batch norm over dimension 1 of x + bias (x [N, B, H], bias [H] or undefined:
// statistics per (node, feature)), affine gamma/beta [N, 1, H], then tanh; differentiable in x,
// gamma and beta. Writes the batch mean and biased variance [N, 1, H] of x + bias to *mean and
// *var (for running statistics). The bias is never added: the normalisation subtracts it again
// (one pass over x fewer); it only shifts the mean, and its gradient is exactly zero (autograd's
// sum of x's gradient would be rounding noise, which Adam would turn into steps of the bias, and
// into different ones on each worker of a data-parallel run).
// sync (not null): the statistics are those of every worker's x together (one sum over the
// workers forward, one backward); *mean and *var are then the whole batch's, the same on every
// worker, and *rows (if not null) is the whole batch's count of rows (x.size(1) without sync).
torch::Tensor BatchNormTanh(const torch::Tensor& x, const torch::Tensor& gamma,
                            const torch::Tensor& beta, double eps, torch::Tensor* mean,
                            torch::Tensor* var, const torch::Tensor& bias = {},
                            const BatchSync* sync = nullptr, double* rows = nullptr);

// Inference: tanh(x * scale + shift), scale/shift [N, 1, H], x [N, B, H]; no gradient.
torch::Tensor ScaleShiftTanh(const torch::Tensor& x, const torch::Tensor& scale,
                             const torch::Tensor& shift);

}  // namespace motionfork
