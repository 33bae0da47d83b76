// The AVX-512 body of node_mix.h (compiled with -march=skylake-avx512, called only when
// that backend runs, backend.h).
#include <immintrin.h>

#include <cstdint>

#include "generator/kernels/backends.h"

namespace motionfork::kernels::avx512 {

namespace {

constexpr int64_t kWidth = 64;  // columns per step: four registers per row

#include "generator/kernels/mask_avx512.inc"

// The masks of the four registers at column j (lanes at or past j1 masked off).
void Masks(int64_t j, int64_t j1, __mmask16 mask[4]) {
  for (int v = 0; v < 4; ++v) mask[v] = Mask(j + 16 * v, j1);
}

// y[n, j..j+63] = sum_m a[n, m] s[m, j..j+63] for every n.
inline void MixStep(const float* a, int64_t nodes, const float* s, int64_t ld, int64_t j,
                    const __mmask16 mask[4], float* y) {
  for (int64_t n = 0; n < nodes; ++n) {
    __m512 acc[4] = {_mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps(),
                     _mm512_setzero_ps()};
    for (int64_t m = 0; m < nodes; ++m) {
      const __m512 w = _mm512_set1_ps(a[n * nodes + m]);
      const float* row = s + m * ld + j;
      for (int v = 0; v < 4; ++v)
        acc[v] = _mm512_fmadd_ps(w, _mm512_maskz_loadu_ps(mask[v], row + 16 * v), acc[v]);
    }
    float* out = y + n * ld + j;
    for (int v = 0; v < 4; ++v) _mm512_mask_storeu_ps(out + 16 * v, mask[v], acc[v]);
  }
}

}  // namespace

void NodeMix(const float* a, int64_t nodes, const float* s, int64_t ld, int64_t j0, int64_t j1,
             float* y) {
  __mmask16 mask[4];
  for (int64_t j = j0; j < j1; j += kWidth) {
    Masks(j, j1, mask);
    MixStep(a, nodes, s, ld, j, mask, y);
  }
}

void NodeMixBackward(const float* at, int64_t nodes, const float* g, const float* s, int64_t ld,
                     int64_t j0, int64_t j1, float* gs, float* ga) {
  // dA's sums as one register of partial sums per (n, m), kept in memory (N x N x 64 bytes:
  // 16 KB at N = 16, L1-resident).
  const int64_t pairs = nodes * nodes;
  __m512* part = static_cast<__m512*>(_mm_malloc(pairs * sizeof(__m512), 64));
  for (int64_t i = 0; i < pairs; ++i) part[i] = _mm512_setzero_ps();
  __mmask16 mask[4];
  for (int64_t j = j0; j < j1; j += kWidth) {
    Masks(j, j1, mask);
    MixStep(at, nodes, g, ld, j, mask, gs);  // leaves the step's rows of g in L1 for dA
    for (int64_t n = 0; n < nodes; ++n) {
      __m512 gn[4];
      for (int v = 0; v < 4; ++v) gn[v] = _mm512_maskz_loadu_ps(mask[v], g + n * ld + j + 16 * v);
      for (int64_t m = 0; m < nodes; ++m) {
        const float* row = s + m * ld + j;
        __m512 acc = part[n * nodes + m];
        for (int v = 0; v < 4; ++v)
          acc = _mm512_fmadd_ps(gn[v], _mm512_maskz_loadu_ps(mask[v], row + 16 * v), acc);
        part[n * nodes + m] = acc;
      }
    }
  }
  for (int64_t i = 0; i < pairs; ++i) ga[i] += _mm512_reduce_add_ps(part[i]);
  _mm_free(part);
}

}  // namespace motionfork::kernels::avx512
