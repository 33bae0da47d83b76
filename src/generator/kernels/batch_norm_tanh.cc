// batch_norm_tanh.h: the portable backend (an AVX-512 one beat it by 6.9% only in an interleaved
// A/B, below the 10% a kernel must earn; BENCHMARKS.md, "Redesign A/B").
#include "generator/kernels/batch_norm_tanh.h"

#include "generator/kernels/backends.h"

namespace motionfork::kernels {

void BatchNormTanhForward(const float* x, int64_t rows, int64_t width, const float* gamma,
                          const float* beta, float eps, float* mean, float* var, float* inv,
                          float* y) {
  portable::BatchNormTanhForward(x, rows, width, gamma, beta, eps, mean, var, inv, y);
}

void BatchNormTanhBackward(const float* gy, const float* x, const float* y, const float* mean,
                           const float* inv, const float* gamma, int64_t rows, int64_t width,
                           float* gx, float* ggamma, float* gbeta, float* gsum) {
  portable::BatchNormTanhBackward(gy, x, y, mean, inv, gamma, rows, width, gx, ggamma, gbeta, gsum);
}

}  // namespace motionfork::kernels
