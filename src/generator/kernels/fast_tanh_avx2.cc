// Compiled with -mavx2 -mfma (see CMakeLists.txt); only called when the CPU supports both.
#include <Eigen/Core>
#include <cstdint>

namespace motionfork::fast::avx2 {
#include "generator/kernels/fast_tanh_kernels.inc"
void Tanh(float* x, int64_t n) { TanhImpl(x, n); }
void ScaleShiftTanh(float* x, const float* s, const float* t, int64_t rows, int64_t g, int64_t w) {
  ScaleShiftTanhImpl(x, s, t, rows, g, w);
}
}  // namespace motionfork::fast::avx2
