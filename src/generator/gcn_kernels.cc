// The parts of gcn_kernels.h that need no AVX-512: the CPU check, buffers, weight packing.
#include "generator/gcn_kernels.h"

#include <cstdlib>
#include <cstring>
#include <new>

namespace motionfork::kernels {

bool Available() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
}

AlignedFloats::AlignedFloats(int64_t n) : data(nullptr, std::free), size(n) {
  if (n <= 0) return;
  const size_t bytes = ((static_cast<size_t>(n) * sizeof(float) + 63) / 64) * 64;
  void* p = std::aligned_alloc(64, bytes);
  if (!p) throw std::bad_alloc();
  std::memset(p, 0, bytes);
  data.reset(static_cast<float*>(p));
}

PackedWeight PackWeight(const float* w, int64_t rows, int64_t cols) {
  PackedWeight p;
  p.rows = rows;
  p.cols = cols;
  p.padded = (cols + 31) / 32 * 32;
  p.data = AlignedFloats(p.padded * rows);
  float* out = p.data.get();
  p.values = out;
  for (int64_t panel = 0; panel < p.padded / 32; ++panel) {
    for (int64_t k = 0; k < rows; ++k) {
      for (int64_t j = 0; j < 32; ++j) {
        const int64_t c = panel * 32 + j;
        out[(panel * rows + k) * 32 + j] = c < cols ? w[k * cols + c] : 0.0f;
      }
    }
  }
  return p;
}

}  // namespace motionfork::kernels
