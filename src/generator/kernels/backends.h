// Internal to the kernels target: each backend's entry points, which the public functions
// (panel_product.h, tanh.h) choose from by ActiveBackend().
// Include only from src/generator/kernels/*.cc. The avx512 ones exist only in builds with
// MOTIONFORK_KERNELS_AVX512 defined (CMakeLists.txt).
#pragma once

#include <cstdint>

#include "generator/kernels/bf16_product.h"
#include "generator/kernels/panel_product.h"

namespace motionfork::kernels {

// The entry points' types: each backend declares its functions with these, so the backends
// cannot drift apart (their definitions spell the same parameters out).
using MatMulFn = void(const float* x, int64_t m, int64_t ldx, const PackedWeight& w, float* z);
using MixRowsFn = void(const LayerEpilogue& e, const float* z, int64_t padded, int64_t width,
                       const float* shared, const int64_t* nodes, int64_t count,
                       const float* residual, float* out, int64_t ld);
using TanhFn = void(float* x, int64_t n);
using MatMulBf16Fn = void(const float* x, int64_t m, int64_t ldx, const PackedWeightBf16& w,
                          float* z);

namespace portable {
MatMulFn MatMul;
MatMulBf16Fn MatMulBf16;
MixRowsFn MixRows;
TanhFn Tanh;
}  // namespace portable

namespace avx512 {
MatMulFn MatMul;
MixRowsFn MixRows;
TanhFn Tanh;
}  // namespace avx512

namespace avx512bf16 {  // only with MOTIONFORK_KERNELS_AVX512BF16
MatMulBf16Fn MatMulBf16;
}  // namespace avx512bf16

}  // namespace motionfork::kernels
