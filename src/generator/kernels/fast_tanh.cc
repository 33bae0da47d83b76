#include "generator/kernels/fast_tanh.h"

#include <Eigen/Core>

namespace motionfork::fast {

namespace avx2 {
void Tanh(float* x, int64_t n);
void ScaleShiftTanh(float* x, const float* s, const float* t, int64_t rows, int64_t g, int64_t w);
}  // namespace avx2

namespace generic {
#include "generator/kernels/fast_tanh_kernels.inc"
}  // namespace generic

namespace {
bool HasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
}
}  // namespace

void Tanh(float* x, int64_t n) {
  if (HasAvx2()) return avx2::Tanh(x, n);
  generic::TanhImpl(x, n);
}

void ScaleShiftTanh(float* x, const float* scale, const float* shift, int64_t rows,
                    int64_t rows_per_group, int64_t width) {
  if (HasAvx2()) return avx2::ScaleShiftTanh(x, scale, shift, rows, rows_per_group, width);
  generic::ScaleShiftTanhImpl(x, scale, shift, rows, rows_per_group, width);
}

}  // namespace motionfork::fast
