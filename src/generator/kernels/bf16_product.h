// Products with bfloat16 inputs and float32 sums (issue 30): the weight matrix rounded to bf16
// once, when packed; each row of X rounded to bf16 as it enters the product; every sum kept in
// float32. On CPUs with AVX512-BF16 (vdpbf16ps: two multiply-adds per 32-bit lane, twice the
// float32 FMA's rate) the AVX512-BF16 kernel runs; elsewhere a portable one computes the same
// products (each bf16 x bf16 product is exact in float32; only the order of the float32 sums
// differs), slowly: for tests, not for speed (UsePortableKernels(true), backend.h, chooses it
// anywhere).
//
// Layout as panel_product.h: Z [M, padded] row-major, W's columns padded to a multiple of 16 and
// cut into panels of kPanelColumns. Within a panel, rows k = 2p and 2p + 1 of W are interleaved:
// one 32-bit word per (p, column) holds W[2p][c] in its low half and W[2p + 1][c] in its high
// half (a zero row pads an odd K), the operand order of vdpbf16ps.
#pragma once

#include <cstdint>

#include "generator/kernels/panel_product.h"

namespace motionfork::kernels {

// True when this build compiled the AVX512-BF16 kernel (MOTIONFORK_KERNELS_AVX512BF16).
bool Bf16KernelBuilt();
// True when that kernel runs here: built, and the CPU has AVX512-BF16 (cpu_features.h).
bool Bf16KernelRuns();

struct PackedWeightBf16 {
  int64_t rows = 0, cols = 0, padded = 0;
  int64_t pairs = 0;   // (rows + 1) / 2
  AlignedFloats data;  // storage of the 32-bit words (pairs * padded)
  const uint32_t* values = nullptr;
};
PackedWeightBf16 PackWeightBf16(const float* w, int64_t rows, int64_t cols);

// Z [M, padded] = bf16(X) bf16(W), float32 sums; row m of X at x + m * ldx; z 64-byte aligned.
void MatMulBf16(const float* x, int64_t m, int64_t ldx, const PackedWeightBf16& w, float* z);

// v rounded to the nearest bfloat16 (ties to even; NaN stays NaN), as a float and as its 16 bits.
float RoundToBf16(float v);
uint16_t Bf16Bits(float v);

}  // namespace motionfork::kernels
