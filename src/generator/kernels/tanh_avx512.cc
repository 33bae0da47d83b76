// The AVX-512 tanh (compiled with -march=skylake-avx512, called only when the AVX-512 backend
// runs; see backend.h).
#include <immintrin.h>

#include <cstdint>

#include "generator/kernels/backends.h"

namespace motionfork::kernels::avx512 {

namespace {
#include "generator/kernels/tanh_avx512.inc"
}  // namespace

void Tanh(float* x, int64_t n) {
  int64_t i = 0;
  for (; i + 64 <= n; i += 64) {
    const __m512 a = Tanh16(_mm512_loadu_ps(x + i)), b = Tanh16(_mm512_loadu_ps(x + i + 16));
    const __m512 c = Tanh16(_mm512_loadu_ps(x + i + 32)), d = Tanh16(_mm512_loadu_ps(x + i + 48));
    _mm512_storeu_ps(x + i, a);
    _mm512_storeu_ps(x + i + 16, b);
    _mm512_storeu_ps(x + i + 32, c);
    _mm512_storeu_ps(x + i + 48, d);
  }
  for (; i + 16 <= n; i += 16) _mm512_storeu_ps(x + i, Tanh16(_mm512_loadu_ps(x + i)));
  if (i < n) {
    const __mmask16 mask = static_cast<__mmask16>((1u << (n - i)) - 1);
    _mm512_mask_storeu_ps(x + i, mask, Tanh16(_mm512_maskz_loadu_ps(mask, x + i)));
  }
}

}  // namespace motionfork::kernels::avx512
