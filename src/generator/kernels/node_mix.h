// AVX-512 kernel for the graph convolution's node mix in training: Y = A S with a small dense
// adjacency A [N, N] and node-major S [N, C] (C = samples x features, 409,600 at the issue's
// sizes). A general matrix product packs S into panels and clears Y before accumulating (three
// extra passes over 26 MB); this reads S once and writes Y once, 64 columns of all N rows at a time
// (N x 256 bytes, L1-resident). No LibTorch. AVX-512 only: call these only when
// ActiveBackend() == Backend::kAvx512 (backend.h; they throw std::logic_error otherwise); the
// portable path is a matrix product, which the caller (model/fused_ops.cc) runs instead.
#pragma once

#include <cstdint>

namespace motionfork::kernels {

// y[n, j] = sum_m a[n, m] s[m, j] for columns j0 <= j < j1; a [N, N] row-major, s and y [N, ld]
// row-major (y may not alias s).
void NodeMix(const float* a, int64_t nodes, const float* s, int64_t ld, int64_t j0, int64_t j1,
             float* y);

// Both gradients of y = A s in one pass over columns j0 <= j < j1 of g = dL/dy and s: gs = A^T g
// (written, [N, ld]) and dA = g s^T, added to ga ([N, N], the caller sums the column ranges).
// at: A^T [N, N] row-major.
void NodeMixBackward(const float* at, int64_t nodes, const float* g, const float* s, int64_t ld,
                     int64_t j0, int64_t j1, float* gs, float* ga);

}  // namespace motionfork::kernels
