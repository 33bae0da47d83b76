// Kernels for the generator's training-mode hidden-layer activation: batch norm over the samples
// of one graph node (statistics per feature) followed by tanh, forward and backward, in a few
// passes over one node's [B, H] slab (1.6 MB at the sizes: it stays in the core's L2
// between passes). Portable code only: an AVX-512 version gained 6.9%, below the 10% a kernel must
// earn (BENCHMARKS.md, "Redesign A/B"). No LibTorch; the caller (model/fused_ops.cc) loops over
// nodes.
//
// Each pass is also a function of its own, so that statistics can be summed over the workers of a
// data-parallel run between the passes (synchronised batch norm): BatchMoments, then
// NormaliseTanh with the whole batch's mean and 1 / sqrt(var + eps); backward TanhNormGradSums,
// then NormGradInput with the whole batch's sums.
#pragma once

#include <cstdint>

namespace motionfork::kernels {

// x, y: [rows, width] row-major (one node's samples); gamma, beta, mean, var, inv: [width].
// mean and var (biased) are the batch statistics, inv = 1 / sqrt(var + eps), and
// y = tanh((x - mean) * inv * gamma + beta).
void BatchNormTanhForward(const float* x, int64_t rows, int64_t width, const float* gamma,
                          const float* beta, float eps, float* mean, float* var, float* inv,
                          float* y);

// The column means and biased variances of x [rows, width].
void BatchMoments(const float* x, int64_t rows, int64_t width, float* mean, float* var);

// y = tanh((x - mean) * inv * gamma + beta).
void NormaliseTanh(const float* x, int64_t rows, int64_t width, const float* mean, const float* inv,
                   const float* gamma, const float* beta, float* y);

// The gradient of the above given gy = dL/dy: gx [rows, width] (may not alias gy) and this node's
// ggamma, gbeta [width]. x, y, mean, inv as the forward pass left them.
void BatchNormTanhBackward(const float* gy, const float* x, const float* y, const float* mean,
                           const float* inv, const float* gamma, int64_t rows, int64_t width,
                           float* gx, float* ggamma, float* gbeta);

// First backward pass: gu = gy * (1 - y^2) (the gradient before the tanh) into gu [rows, width]
// (may not alias gy), gbeta = the column sums of gu, ggamma = those of gu * xhat, with
// xhat = (x - mean) * inv.
void TanhNormGradSums(const float* gy, const float* x, const float* y, const float* mean,
                      const float* inv, int64_t rows, int64_t width, float* gu, float* ggamma,
                      float* gbeta);

// Second backward pass, in place on gu: gx = gamma * inv / count *
// (count * gu - sum_gu - xhat * sum_gu_xhat). One worker: count = rows, sum_gu = gbeta and
// sum_gu_xhat = ggamma of TanhNormGradSums.
void NormGradInput(float* gu, const float* x, const float* mean, const float* inv,
                   const float* gamma, int64_t rows, int64_t width, float count,
                   const float* sum_gu, const float* sum_gu_xhat);

}  // namespace motionfork::kernels
