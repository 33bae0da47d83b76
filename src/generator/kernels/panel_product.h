// Fused kernels for generator inference (no LibTorch, no autograd): one graph-conv layer
// Y = act((A (X W) + b) * s + t) [+ R] computed sample by sample, with the weight matrix packed
// once and the adjacency mix, batch-norm scale and shift, tanh and residual applied while the
// sample's rows are still in the core's cache.
//
// Layout: sample-major [B, N, F]: sample b's N node rows are contiguous (row n at (b * N + n) * F).
// MatMul and MixRows run the AVX-512 backend or the portable one (backend.h); both run anywhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

namespace motionfork::kernels {

// A float buffer aligned to 64 bytes (one AVX-512 register), zero-filled unless zero = false.
struct AlignedFloats {
  std::unique_ptr<float, void (*)(void*)> data{nullptr, nullptr};
  int64_t size = 0;
  explicit AlignedFloats(int64_t n = 0, bool zero = true);
  float* get() const { return data.get(); }
};

// W [K, H] row-major, packed for the kernels: H padded with zeros to a multiple of 16 (`padded`),
// cut into panels of kPanelColumns columns (the last one narrower), each stored [K][width].
constexpr int64_t kPanelColumns = 48;
struct PackedWeight {
  int64_t rows = 0, cols = 0, padded = 0;
  AlignedFloats data;
  const float* values = nullptr;  // data.get()
};
PackedWeight PackWeight(const float* w, int64_t rows, int64_t cols);

// Z [M, padded] = X [M, K] W; row m of X at x + m * ldx. z is 64-byte aligned, row stride padded.
// Each row is one sequence of multiply-adds over K: it does not depend on M or the rows around it.
void MatMul(const float* x, int64_t m, int64_t ldx, const PackedWeight& w, float* z);

// What turns the product rows Z of one sample into the layer's output rows.
struct LayerEpilogue {
  int64_t nodes = 0;                 // N
  const float* adjacency = nullptr;  // [N, N]: out row n mixes Z rows with A[n, :]
  const float* scale = nullptr;      // [N, padded]: per node and feature (batch norm), or null = 1
  const float* shift = nullptr;      // [N, padded]: bias, batch norm folded in
  // Optional per-sample row added to every node before mixing (the latent's z W_z): out row n
  // gets rowsum(A)[n] * shared[:] (rowsum: [N]).
  const float* rowsum = nullptr;
  bool tanh = false;
};

// For one sample: out[n, :H] = act(scale[n] * (sum_m A[n, m] Z[m] + rowsum[n] * shared) + shift[n])
// (+ residual[n, :H] when residual is not null), for the nodes listed in `nodes` (null: all N, in
// order). z: the sample's N product rows (stride padded); shared: [padded] or null; out and
// residual rows have stride ld (they may be the same rows: the update is in place).
void MixRows(const LayerEpilogue& e, const float* z, int64_t padded, int64_t width,
             const float* shared, const int64_t* nodes, int64_t count, const float* residual,
             float* out, int64_t ld);

}  // namespace motionfork::kernels
