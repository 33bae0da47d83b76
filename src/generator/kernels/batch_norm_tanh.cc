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

void BatchNormTanhForward(const float* x, int64_t rows, int64_t width, const float* gamma,
                          const float* beta, float eps, float* mean, float* var, float* inv,
                          float* y) {
  const int64_t B = rows, H = width;
  Row m(mean, H), v(var, H), iv(inv, H);
  m.setZero();
  v.setZero();
  for (int64_t b = 0; b < B; ++b) m += ConstRow(x + b * H, H);
  m /= static_cast<float>(B);
  for (int64_t b = 0; b < B; ++b) v += (ConstRow(x + b * H, H) - m).square();
  v /= static_cast<float>(B);
  iv = (v + eps).rsqrt();
  const Eigen::ArrayXf k = iv * ConstRow(gamma, H);
  for (int64_t b = 0; b < B; ++b) {
    Row(y + b * H, H) = (ConstRow(x + b * H, H) - m) * k + ConstRow(beta, H);
  }
  portable::Tanh(y, B * H);
}

void BatchNormTanhBackward(const float* gy, const float* x, const float* y, const float* mean,
                           const float* inv, const float* gamma, int64_t rows, int64_t width,
                           float* gx, float* ggamma, float* gbeta, float* gsum) {
  const int64_t B = rows, H = width;
  Row gg(ggamma, H), gb(gbeta, H);
  const ConstRow m(mean, H), iv(inv, H);
  gg.setZero();
  gb.setZero();
  // gu = gy * (1 - y^2), kept in gx for now; xhat = (x - mean) * inv.
  for (int64_t b = 0; b < B; ++b) {
    const int64_t r = b * H;
    Row gu(gx + r, H);
    const ConstRow yy(y + r, H);
    gu = ConstRow(gy + r, H) * (1.0f - yy * yy);
    gb += gu;
    gg += gu * (ConstRow(x + r, H) - m) * iv;
  }
  // gx = gamma * inv / B * (B * gu - sum(gu) - xhat * sum(gu * xhat))
  const Eigen::ArrayXf k = ConstRow(gamma, H) * iv / static_cast<float>(B);
  Row sum(gsum, H);
  sum.setZero();
  for (int64_t b = 0; b < B; ++b) {
    const int64_t r = b * H;
    Row g(gx + r, H);
    g = k * (static_cast<float>(B) * g - gb - (ConstRow(x + r, H) - m) * iv * gg);
    sum += g;
  }
}

}  // namespace motionfork::kernels
