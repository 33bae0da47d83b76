// X W with bfloat16 inputs and float32 sums for training (issue 30), differentiable in X and W:
// the forward product and both backward products (dX = dY W^T, dW = X^T dY) run on
// kernels::MatMulBf16 (kernels/bf16_product.h: the AVX512-BF16 kernel where the CPU has it, the
// portable one elsewhere, for tests). Each operand is rounded to bf16 as it enters a product; every
// sum, the result and the gradients stay float32. The weight is packed afresh each call: it changes
// every step.
#pragma once

#include <torch/torch.h>

namespace motionfork {

// x [M, K], w [K, N], float32; returns [M, N] float32.
torch::Tensor Bf16MatMul(const torch::Tensor& x, const torch::Tensor& w);

}  // namespace motionfork
