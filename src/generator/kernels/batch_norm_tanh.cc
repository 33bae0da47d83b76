// The choice of backend for batch_norm_tanh.h.
#include "generator/kernels/batch_norm_tanh.h"

#include "generator/kernels/backend.h"
#include "generator/kernels/backends.h"

namespace motionfork::kernels {

void BatchNormTanhForward(const float* x, int64_t rows, int64_t width, const float* gamma,
                          const float* beta, float eps, float* mean, float* var, float* inv,
                          float* y) {
#ifdef MOTIONFORK_KERNELS_AVX512
  if (ActiveBackend() == Backend::kAvx512)
    return avx512::BatchNormTanhForward(x, rows, width, gamma, beta, eps, mean, var, inv, y);
#endif
  portable::BatchNormTanhForward(x, rows, width, gamma, beta, eps, mean, var, inv, y);
}

void BatchNormTanhBackward(const float* gy, const float* x, const float* y, const float* mean,
                           const float* inv, const float* gamma, int64_t rows, int64_t width,
                           float* gx, float* ggamma, float* gbeta, float* gsum) {
#ifdef MOTIONFORK_KERNELS_AVX512
  if (ActiveBackend() == Backend::kAvx512) {
    return avx512::BatchNormTanhBackward(gy, x, y, mean, inv, gamma, rows, width, gx, ggamma, gbeta,
                                         gsum);
  }
#endif
  portable::BatchNormTanhBackward(gy, x, y, mean, inv, gamma, rows, width, gx, ggamma, gbeta, gsum);
}

}  // namespace motionfork::kernels
