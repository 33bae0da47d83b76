// The parts of panel_product.h that need no AVX-512: the CPU check, buffers, weight packing.
#include "generator/kernels/panel_product.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <new>

namespace motionfork::kernels {

bool Available() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
}

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

}  // namespace motionfork::kernels
