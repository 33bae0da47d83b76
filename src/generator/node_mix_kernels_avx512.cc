// The AVX-512 body of node_mix_kernels.h (compiled with -march=skylake-avx512, called only when
// kernels::Available()).
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "generator/node_mix_kernels.h"

namespace motionfork::kernels {

void NodeMix(const float* a, int64_t nodes, const float* s, int64_t ld, int64_t j0, int64_t j1, float* y) {
  constexpr int64_t kWidth = 64;  // four registers per output row
  for (int64_t j = j0; j < j1; j += kWidth) {
    // Lanes past j1 are masked: loads give zeros, stores do nothing.
    __mmask16 mask[4];
    for (int v = 0; v < 4; ++v) {
      const int64_t left = std::clamp<int64_t>(j1 - (j + 16 * v), 0, 16);
      mask[v] = static_cast<__mmask16>((1u << left) - 1);
    }
    for (int64_t n = 0; n < nodes; ++n) {
      __m512 acc[4] = {_mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps()};
      for (int64_t m = 0; m < nodes; ++m) {
        const __m512 w = _mm512_set1_ps(a[n * nodes + m]);
        const float* row = s + m * ld + j;
        for (int v = 0; v < 4; ++v) acc[v] = _mm512_fmadd_ps(w, _mm512_maskz_loadu_ps(mask[v], row + 16 * v), acc[v]);
      }
      float* out = y + n * ld + j;
      for (int v = 0; v < 4; ++v) _mm512_mask_storeu_ps(out + 16 * v, mask[v], acc[v]);
    }
  }
}

}  // namespace motionfork::kernels
