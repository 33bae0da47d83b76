// Buffers, weight packing and the choice of backend for panel_product.h.
#include "generator/kernels/panel_product.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <new>

#include "generator/kernels/backend.h"
#include "generator/kernels/backends.h"

namespace motionfork::kernels {

AlignedFloats::AlignedFloats(int64_t n, bool zero) : data(nullptr, std::free), size(n) {
  if (n <= 0) return;
  const size_t bytes = ((static_cast<size_t>(n) * sizeof(float) + 63) / 64) * 64;
  void* p = std::aligned_alloc(64, bytes);
  if (!p) throw std::bad_alloc();
  if (zero) std::memset(p, 0, bytes);
  data.reset(static_cast<float*>(p));
}

PackedWeight PackWeight(const float* w, int64_t rows, int64_t cols) {
  PackedWeight p;
  p.rows = rows;
  p.cols = cols;
  p.padded = (cols + 15) / 16 * 16;
  p.data = AlignedFloats(p.padded * rows);
  float* out = p.data.get();
  p.values = out;
  for (int64_t c0 = 0; c0 < p.padded; c0 += kPanelColumns) {
    const int64_t width = std::min(kPanelColumns, p.padded - c0);
    for (int64_t k = 0; k < rows; ++k) {
      for (int64_t j = 0; j < width; ++j) {
        const int64_t c = c0 + j;
        *out++ = c < cols ? w[k * cols + c] : 0.0f;
      }
    }
  }
  return p;
}

void MatMul(const float* x, int64_t m, int64_t ldx, const PackedWeight& w, float* z) {
#ifdef MOTIONFORK_KERNELS_AVX512
  if (ActiveBackend() == Backend::kAvx512) return avx512::MatMul(x, m, ldx, w, z);
#endif
  portable::MatMul(x, m, ldx, w, z);
}

void MixRows(const LayerEpilogue& e, const float* z, int64_t padded, int64_t width,
             const float* shared, const int64_t* nodes, int64_t count, const float* residual,
             float* out, int64_t ld) {
#ifdef MOTIONFORK_KERNELS_AVX512
  if (ActiveBackend() == Backend::kAvx512)
    return avx512::MixRows(e, z, padded, width, shared, nodes, count, residual, out, ld);
#endif
  portable::MixRows(e, z, padded, width, shared, nodes, count, residual, out, ld);
}

}  // namespace motionfork::kernels
