// The AVX-512 bodies of batch_norm_tanh.h (compiled with -march=skylake-avx512, called only
// when that backend runs, backend.h). The passes over one node's rows run on a block of 64 columns
// (four registers) at a time: the block's slabs of x, y, gy and gx (1600 rows: 400 KB each) stay in
// L2 from one pass to the next, so each is read from memory once, and the per-feature sums stay in
// registers over all rows (sums kept in memory made every row wait for the previous row's store).
#include <immintrin.h>

#include <cstdint>

#include "generator/kernels/backends.h"

namespace motionfork::kernels::avx512 {
namespace {

#include "generator/kernels/mask_avx512.inc"
#include "generator/kernels/tanh_avx512.inc"

constexpr int kBlockVectors = 4;
constexpr int64_t kBlockColumns = 16 * kBlockVectors;
constexpr int64_t kAhead = 8;  // rows prefetched ahead in the backward pass's first sweep

inline __m512 Load(const float* p, __mmask16 m) { return _mm512_maskz_loadu_ps(m, p); }
inline void Store(float* p, __mmask16 m, __m512 v) { _mm512_mask_storeu_ps(p, m, v); }

// Columns [h0, h1) of one node (h1 - h0 <= kBlockColumns).
void ForwardBlock(const float* x, int64_t rows, int64_t width, int64_t h0, int64_t h1,
                  const float* gamma, const float* beta, float eps, float* mean, float* var,
                  float* inv, float* y) {
  __mmask16 m[kBlockVectors];
  __m512 sum[kBlockVectors], mu[kBlockVectors], k[kBlockVectors], b[kBlockVectors];
  for (int v = 0; v < kBlockVectors; ++v) {
    m[v] = Mask(h0 + 16 * v, h1);
    sum[v] = _mm512_setzero_ps();
  }
  for (int64_t r = 0; r < rows; ++r) {
    const float* xr = x + r * width + h0;
    for (int v = 0; v < kBlockVectors; ++v) sum[v] = _mm512_add_ps(sum[v], Load(xr + 16 * v, m[v]));
  }
  const __m512 per_row = _mm512_set1_ps(1.0f / static_cast<float>(rows));
  for (int v = 0; v < kBlockVectors; ++v) {
    mu[v] = _mm512_mul_ps(sum[v], per_row);
    sum[v] = _mm512_setzero_ps();
  }
  for (int64_t r = 0; r < rows; ++r) {
    const float* xr = x + r * width + h0;
    for (int v = 0; v < kBlockVectors; ++v) {
      const __m512 d = _mm512_sub_ps(Load(xr + 16 * v, m[v]), mu[v]);
      sum[v] = _mm512_fmadd_ps(d, d, sum[v]);
    }
  }
  for (int v = 0; v < kBlockVectors; ++v) {
    const int64_t h = h0 + 16 * v;
    Store(mean + h, m[v], mu[v]);
    Store(var + h, m[v], _mm512_mul_ps(sum[v], per_row));
  }
  for (int64_t h = h0; h < h1; ++h) inv[h] = 1.0f / __builtin_sqrtf(var[h] + eps);
  for (int v = 0; v < kBlockVectors; ++v) {
    const int64_t h = h0 + 16 * v;
    k[v] = _mm512_mul_ps(Load(inv + h, m[v]), Load(gamma + h, m[v]));
    b[v] = Load(beta + h, m[v]);
  }
  // y = tanh((x - mean) * inv * gamma + beta)
  for (int64_t r = 0; r < rows; ++r) {
    const float* xr = x + r * width + h0;
    float* yr = y + r * width + h0;
    for (int v = 0; v < kBlockVectors; ++v) {
      const __m512 u = _mm512_fmadd_ps(_mm512_sub_ps(Load(xr + 16 * v, m[v]), mu[v]), k[v], b[v]);
      Store(yr + 16 * v, m[v], Tanh16(u));
    }
  }
}

void BackwardBlock(const float* gy, const float* x, const float* y, const float* mean,
                   const float* inv, const float* gamma, int64_t rows, int64_t width, int64_t h0,
                   int64_t h1, float* gx, float* ggamma, float* gbeta, float* gsum) {
  __mmask16 m[kBlockVectors];
  __m512 mu[kBlockVectors], iv[kBlockVectors], gb[kBlockVectors], gg[kBlockVectors];
  for (int v = 0; v < kBlockVectors; ++v) {
    const int64_t h = h0 + 16 * v;
    m[v] = Mask(h, h1);
    mu[v] = Load(mean + h, m[v]);
    iv[v] = Load(inv + h, m[v]);
    gb[v] = gg[v] = _mm512_setzero_ps();
  }
  const __m512 one = _mm512_set1_ps(1.0f);
  // gu = gy * (1 - y^2), the gradient before tanh, kept in gx; gbeta = sum gu, ggamma = sum gu
  // xhat.
  for (int64_t r = 0; r < rows; ++r) {
    const int64_t o = r * width + h0;
    if (r + kAhead < rows) {
      const int64_t a = o + kAhead * width;
      for (int v = 0; v < kBlockVectors; ++v) {
        _mm_prefetch(reinterpret_cast<const char*>(gy + a + 16 * v), _MM_HINT_T0);
        _mm_prefetch(reinterpret_cast<const char*>(y + a + 16 * v), _MM_HINT_T0);
        _mm_prefetch(reinterpret_cast<const char*>(x + a + 16 * v), _MM_HINT_T0);
      }
    }
    for (int v = 0; v < kBlockVectors; ++v) {
      const __m512 yy = Load(y + o + 16 * v, m[v]);
      const __m512 gu = _mm512_mul_ps(Load(gy + o + 16 * v, m[v]), _mm512_fnmadd_ps(yy, yy, one));
      const __m512 xhat = _mm512_mul_ps(_mm512_sub_ps(Load(x + o + 16 * v, m[v]), mu[v]), iv[v]);
      Store(gx + o + 16 * v, m[v], gu);
      gb[v] = _mm512_add_ps(gb[v], gu);
      gg[v] = _mm512_fmadd_ps(gu, xhat, gg[v]);
    }
  }
  // gx = gamma * inv / B * (B * gu - gbeta - xhat * ggamma)
  const __m512 vb = _mm512_set1_ps(static_cast<float>(rows));
  const __m512 per_row = _mm512_set1_ps(1.0f / static_cast<float>(rows));
  __m512 k[kBlockVectors], sum[kBlockVectors];
  for (int v = 0; v < kBlockVectors; ++v) {
    sum[v] = _mm512_setzero_ps();
    const int64_t h = h0 + 16 * v;
    Store(gbeta + h, m[v], gb[v]);
    Store(ggamma + h, m[v], gg[v]);
    k[v] = _mm512_mul_ps(_mm512_mul_ps(Load(gamma + h, m[v]), iv[v]), per_row);
  }
  for (int64_t r = 0; r < rows; ++r) {
    const int64_t o = r * width + h0;
    for (int v = 0; v < kBlockVectors; ++v) {
      const __m512 xhat = _mm512_mul_ps(_mm512_sub_ps(Load(x + o + 16 * v, m[v]), mu[v]), iv[v]);
      const __m512 inner =
          _mm512_fnmadd_ps(xhat, gg[v], _mm512_fmsub_ps(vb, Load(gx + o + 16 * v, m[v]), gb[v]));
      const __m512 g = _mm512_mul_ps(k[v], inner);
      Store(gx + o + 16 * v, m[v], g);
      sum[v] = _mm512_add_ps(sum[v], g);
    }
  }
  for (int v = 0; v < kBlockVectors; ++v) Store(gsum + h0 + 16 * v, m[v], sum[v]);
}

}  // namespace

void BatchNormTanhForward(const float* x, int64_t rows, int64_t width, const float* gamma,
                          const float* beta, float eps, float* mean, float* var, float* inv,
                          float* y) {
  for (int64_t h0 = 0; h0 < width; h0 += kBlockColumns) {
    const int64_t h1 = h0 + kBlockColumns < width ? h0 + kBlockColumns : width;
    ForwardBlock(x, rows, width, h0, h1, gamma, beta, eps, mean, var, inv, y);
  }
}

void BatchNormTanhBackward(const float* gy, const float* x, const float* y, const float* mean,
                           const float* inv, const float* gamma, int64_t rows, int64_t width,
                           float* gx, float* ggamma, float* gbeta, float* gsum) {
  for (int64_t h0 = 0; h0 < width; h0 += kBlockColumns) {
    const int64_t h1 = h0 + kBlockColumns < width ? h0 + kBlockColumns : width;
    BackwardBlock(gy, x, y, mean, inv, gamma, rows, width, h0, h1, gx, ggamma, gbeta, gsum);
  }
}

}  // namespace motionfork::kernels::avx512
