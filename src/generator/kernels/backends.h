// Internal to the kernels target: each backend's entry points, which the public functions
// (panel_product.h, tanh.h) choose from by ActiveBackend().
// Include only from src/generator/kernels/*.cc. The avx512 ones exist only in builds with
// MOTIONFORK_KERNELS_AVX512 defined (CMakeLists.txt).
#pragma once

#include <cstdint>

#include "generator/kernels/panel_product.h"

namespace motionfork::kernels {

namespace portable {
void MatMul(const float* x, int64_t m, int64_t ldx, const PackedWeight& w, float* z);
void MixRows(const LayerEpilogue& e, const float* z, int64_t padded, int64_t width,
             const float* shared, const int64_t* nodes, int64_t count, const float* residual,
             float* out, int64_t ld);
void Tanh(float* x, int64_t n);
}  // namespace portable

namespace avx512 {
void MatMul(const float* x, int64_t m, int64_t ldx, const PackedWeight& w, float* z);
void MixRows(const LayerEpilogue& e, const float* z, int64_t padded, int64_t width,
             const float* shared, const int64_t* nodes, int64_t count, const float* residual,
             float* out, int64_t ld);
void Tanh(float* x, int64_t n);
}  // namespace avx512

}  // namespace motionfork::kernels
