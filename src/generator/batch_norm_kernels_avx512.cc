// The AVX-512 bodies of batch_norm_kernels.h (compiled with -march=skylake-avx512, called only
// when kernels::Available()). Every loop runs over rows, then over the width 16 floats at a time
// (the last block masked); the per-feature sums live in the output arrays, which stay in L1.
#include <immintrin.h>

#include <cstdint>

#include "generator/batch_norm_kernels.h"

namespace motionfork::kernels {
namespace {

#include "generator/tanh_avx512.inc"

inline __mmask16 Mask(int64_t remaining) {
  return remaining >= 16 ? static_cast<__mmask16>(0xFFFF) : static_cast<__mmask16>((1u << remaining) - 1);
}

inline __m512 Load(const float* p, __mmask16 m) { return _mm512_maskz_loadu_ps(m, p); }
inline void Store(float* p, __mmask16 m, __m512 v) { _mm512_mask_storeu_ps(p, m, v); }

}  // namespace

void BatchNormTanhForward(const float* x, int64_t rows, int64_t width, const float* gamma,
                          const float* beta, float eps, float* mean, float* var, float* inv, float* y) {
  for (int64_t h = 0; h < width; ++h) mean[h] = var[h] = 0.0f;
  for (int64_t r = 0; r < rows; ++r) {
    const float* xr = x + r * width;
    for (int64_t h = 0; h < width; h += 16) {
      const __mmask16 m = Mask(width - h);
      Store(mean + h, m, _mm512_add_ps(Load(mean + h, m), Load(xr + h, m)));
    }
  }
  const __m512 scale = _mm512_set1_ps(1.0f / static_cast<float>(rows));
  for (int64_t h = 0; h < width; h += 16) {
    const __mmask16 m = Mask(width - h);
    Store(mean + h, m, _mm512_mul_ps(Load(mean + h, m), scale));
  }
  for (int64_t r = 0; r < rows; ++r) {
    const float* xr = x + r * width;
    for (int64_t h = 0; h < width; h += 16) {
      const __mmask16 m = Mask(width - h);
      const __m512 d = _mm512_sub_ps(Load(xr + h, m), Load(mean + h, m));
      Store(var + h, m, _mm512_fmadd_ps(d, d, Load(var + h, m)));
    }
  }
  const __m512 veps = _mm512_set1_ps(eps);
  for (int64_t h = 0; h < width; h += 16) {
    const __mmask16 m = Mask(width - h);
    const __m512 v = _mm512_mul_ps(Load(var + h, m), scale);
    Store(var + h, m, v);
    Store(inv + h, m, _mm512_div_ps(_mm512_set1_ps(1.0f), _mm512_sqrt_ps(_mm512_add_ps(v, veps))));
  }
  for (int64_t r = 0; r < rows; ++r) {
    const float* xr = x + r * width;
    float* yr = y + r * width;
    for (int64_t h = 0; h < width; h += 16) {
      const __mmask16 m = Mask(width - h);
      // (x - mean) * inv * gamma + beta
      const __m512 k = _mm512_mul_ps(Load(inv + h, m), Load(gamma + h, m));
      const __m512 u = _mm512_fmadd_ps(_mm512_sub_ps(Load(xr + h, m), Load(mean + h, m)), k, Load(beta + h, m));
      Store(yr + h, m, Tanh16(u));
    }
  }
}

void BatchNormTanhBackward(const float* gy, const float* x, const float* y, const float* mean,
                           const float* inv, const float* gamma, int64_t rows, int64_t width,
                           float* gx, float* ggamma, float* gbeta) {
  for (int64_t h = 0; h < width; ++h) ggamma[h] = gbeta[h] = 0.0f;
  const __m512 one = _mm512_set1_ps(1.0f);
  // gu = gy * (1 - y^2), the gradient before tanh, kept in gx; gbeta = sum gu, ggamma = sum gu xhat.
  for (int64_t r = 0; r < rows; ++r) {
    const int64_t o = r * width;
    for (int64_t h = 0; h < width; h += 16) {
      const __mmask16 m = Mask(width - h);
      const __m512 yy = Load(y + o + h, m);
      const __m512 gu = _mm512_mul_ps(Load(gy + o + h, m), _mm512_fnmadd_ps(yy, yy, one));
      const __m512 xhat = _mm512_mul_ps(_mm512_sub_ps(Load(x + o + h, m), Load(mean + h, m)), Load(inv + h, m));
      Store(gx + o + h, m, gu);
      Store(gbeta + h, m, _mm512_add_ps(Load(gbeta + h, m), gu));
      Store(ggamma + h, m, _mm512_fmadd_ps(gu, xhat, Load(ggamma + h, m)));
    }
  }
  // gx = gamma * inv / B * (B * gu - gbeta - xhat * ggamma)
  const __m512 vb = _mm512_set1_ps(static_cast<float>(rows));
  const __m512 per_row = _mm512_set1_ps(1.0f / static_cast<float>(rows));
  for (int64_t r = 0; r < rows; ++r) {
    const int64_t o = r * width;
    for (int64_t h = 0; h < width; h += 16) {
      const __mmask16 m = Mask(width - h);
      const __m512 iv = Load(inv + h, m);
      const __m512 k = _mm512_mul_ps(_mm512_mul_ps(Load(gamma + h, m), iv), per_row);
      const __m512 xhat = _mm512_mul_ps(_mm512_sub_ps(Load(x + o + h, m), Load(mean + h, m)), iv);
      const __m512 inner = _mm512_fnmadd_ps(xhat, Load(ggamma + h, m),
                                            _mm512_fmsub_ps(vb, Load(gx + o + h, m), Load(gbeta + h, m)));
      Store(gx + o + h, m, _mm512_mul_ps(k, inner));
    }
  }
}

}  // namespace motionfork::kernels
