// Fused graph-layer activations with hand-written backward passes (LibTorch autograd functions).
//
// The generator's hidden layers end in batch norm + tanh on [N, B, H] tensors: as separate
// LibTorch ops that is about eight passes over memory forward and more backward, which costs
// more than the layer's matrix products. These do it in one pass each way.
#pragma once

#include <torch/torch.h>

namespace motionfork {

// tanh(x) by kernels::Tanh (kernels/tanh.h), x any contiguous float tensor; differentiable.
torch::Tensor FusedTanh(const torch::Tensor& x);

// Training-mode batch norm over dimension 1 of x + bias (x [N, B, H], bias [H] or undefined:
// statistics per (node, feature)), affine gamma/beta [N, 1, H], then tanh; differentiable in x,
// gamma, beta and bias. Writes the batch mean and biased variance [N, 1, H] of x + bias to *mean
// and *var (for running statistics). The bias is never added: the normalisation subtracts it again
// (one pass over x fewer); it only shifts the mean, and its gradient is the sum of x's.
torch::Tensor BatchNormTanh(const torch::Tensor& x, const torch::Tensor& gamma,
                            const torch::Tensor& beta, double eps, torch::Tensor* mean,
                            torch::Tensor* var, const torch::Tensor& bias = {});

// Inference: tanh(x * scale + shift), scale/shift [N, 1, H], x [N, B, H]; no gradient.
torch::Tensor ScaleShiftTanh(const torch::Tensor& x, const torch::Tensor& scale,
                             const torch::Tensor& shift);

}  // namespace motionfork
