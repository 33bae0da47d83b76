// batch_norm_tanh.h in portable code (Eigen arrays): an AVX-512 version gained 6.9% only, below
// the 10% a kernel must earn (BENCHMARKS.md, "Redesign A/B").
#include "generator/kernels/batch_norm_tanh.h"

#include <Eigen/Core>

#include "generator/kernels/backends.h"

namespace motionfork::kernels {

namespace {
using Row = Eigen::Map<Eigen::ArrayXf>;
using ConstRow = Eigen::Map<const Eigen::ArrayXf>;
}  // namespace

void BatchMoments(const float* x, int64_t rows, int64_t width, float* mean, float* var) {
  const int64_t B = rows, H = width;
  Row m(mean, H), v(var, H);
  m.setZero();
  v.setZero();
  for (int64_t b = 0; b < B; ++b) m += ConstRow(x + b * H, H);
  m /= static_cast<float>(B);
  for (int64_t b = 0; b < B; ++b) v += (ConstRow(x + b * H, H) - m).square();
  v /= static_cast<float>(B);
}

void NormaliseTanh(const float* x, int64_t rows, int64_t width, const float* mean, const float* inv,
                   const float* gamma, const float* beta, float* y) {
  const int64_t B = rows, H = width;
  const ConstRow m(mean, H);
  const Eigen::ArrayXf k = ConstRow(inv, H) * ConstRow(gamma, H);
  for (int64_t b = 0; b < B; ++b) {
    Row(y + b * H, H) = (ConstRow(x + b * H, H) - m) * k + ConstRow(beta, H);
  }
  portable::Tanh(y, B * H);
}

void BatchNormTanhForward(const float* x, int64_t rows, int64_t width, const float* gamma,
                          const float* beta, float eps, float* mean, float* var, float* inv,
                          float* y) {
  BatchMoments(x, rows, width, mean, var);
  Row(inv, width) = (ConstRow(var, width) + eps).rsqrt();
  NormaliseTanh(x, rows, width, mean, inv, gamma, beta, y);
}

void TanhNormGradSums(const float* gy, const float* x, const float* y, const float* mean,
                      const float* inv, int64_t rows, int64_t width, float* gu, float* ggamma,
                      float* gbeta) {
  const int64_t B = rows, H = width;
  Row gg(ggamma, H), gb(gbeta, H);
  const ConstRow m(mean, H), iv(inv, H);
  gg.setZero();
  gb.setZero();
  for (int64_t b = 0; b < B; ++b) {
    const int64_t r = b * H;
    Row g(gu + r, H);
    const ConstRow yy(y + r, H);
    g = ConstRow(gy + r, H) * (1.0f - yy * yy);
    gb += g;
    gg += g * (ConstRow(x + r, H) - m) * iv;
  }
}

void NormGradInput(float* gu, const float* x, const float* mean, const float* inv,
                   const float* gamma, int64_t rows, int64_t width, float count,
                   const float* sum_gu, const float* sum_gu_xhat) {
  const int64_t B = rows, H = width;
  const ConstRow m(mean, H), iv(inv, H), sg(sum_gu, H), sgx(sum_gu_xhat, H);
  const Eigen::ArrayXf k = ConstRow(gamma, H) * iv / count;
  for (int64_t b = 0; b < B; ++b) {
    const int64_t r = b * H;
    Row g(gu + r, H);
    g = k * (count * g - sg - (ConstRow(x + r, H) - m) * iv * sgx);
  }
}

void BatchNormTanhBackward(const float* gy, const float* x, const float* y, const float* mean,
                           const float* inv, const float* gamma, int64_t rows, int64_t width,
                           float* gx, float* ggamma, float* gbeta) {
  TanhNormGradSums(gy, x, y, mean, inv, rows, width, gx, ggamma, gbeta);
  NormGradInput(gx, x, mean, inv, gamma, rows, width, static_cast<float>(rows), gbeta, ggamma);
}

}  // namespace motionfork::kernels
