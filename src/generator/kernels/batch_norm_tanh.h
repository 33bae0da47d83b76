// Kernels for the generator's training-mode hidden-layer activation: batch norm over the samples
// of one graph node (statistics per feature) followed by tanh, forward and backward, in a few
// passes over one node's [B, H] slab (1.6 MB at the sizes: it stays in the core's L2
// between passes). Portable code only: an AVX-512 version gained 6.9%, below the 10% a kernel must
// earn (BENCHMARKS.md, "Redesign A/B"). No LibTorch; the caller (model/fused_ops.cc) loops over
// nodes.
#pragma once

#include <cstdint>

namespace motionfork::kernels {

// x, y: [rows, width] row-major (one node's samples); gamma, beta, mean, var, inv: [width].
// mean and var (biased) are the batch statistics, inv = 1 / sqrt(var + eps), and
// y = tanh((x - mean) * inv * gamma + beta).
void BatchNormTanhForward(const float* x, int64_t rows, int64_t width, const float* gamma,
                          const float* beta, float eps, float* mean, float* var, float* inv,
                          float* y);

// The gradient of the above given gy = dL/dy: gx [rows, width] (may not alias gy), this node's
// ggamma, gbeta [width] and gsum [width], the column sums of gx (the gradient of a bias added to x
// before the batch norm, which the normalisation cancels). x, y, mean, inv as the forward pass left
// them.
void BatchNormTanhBackward(const float* gy, const float* x, const float* y, const float* mean,
                           const float* inv, const float* gamma, int64_t rows, int64_t width,
                           float* gx, float* ggamma, float* gbeta, float* gsum);

}  // namespace motionfork::kernels
