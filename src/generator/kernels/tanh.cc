#include "generator/kernels/tanh.h"

#include <algorithm>

#include "generator/kernels/backend.h"
#include "generator/kernels/backends.h"

namespace motionfork::kernels {

void Tanh(float* x, int64_t n) {
#ifdef MOTIONFORK_KERNELS_AVX512
  if (ActiveBackend() == Backend::kAvx512) return avx512::Tanh(x, n);
#endif
  portable::Tanh(x, n);
}

void ScaleShiftTanh(float* x, const float* scale, const float* shift, int64_t rows,
                    int64_t rows_per_group, int64_t width) {
  // A few rows at a time: scaled and shifted, then tanh while they are in the L1 cache.
  constexpr int64_t kBlock = 4096;  // floats
  const int64_t block_rows = std::max<int64_t>(1, kBlock / std::max<int64_t>(1, width));
  for (int64_t r0 = 0; r0 < rows; r0 += block_rows) {
    const int64_t r1 = std::min(rows, r0 + block_rows);
    for (int64_t r = r0; r < r1; ++r) {
      const int64_t g = r / rows_per_group;
      float* row = x + r * width;
      const float *s = scale + g * width, *t = shift + g * width;
      for (int64_t i = 0; i < width; ++i) row[i] = row[i] * s[i] + t[i];
    }
    Tanh(x + r0 * width, (r1 - r0) * width);
  }
}

}  // namespace motionfork::kernels
