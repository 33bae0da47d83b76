// Weight packing, rounding, the portable kernel and the choice of kernel for bf16_product.h.
#include "generator/kernels/bf16_product.h"

#include <algorithm>
#include <cstring>

#include "generator/kernels/backend.h"
#include "generator/kernels/backends.h"
#include "generator/kernels/cpu_features.h"

namespace motionfork::kernels {

uint16_t Bf16Bits(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  if ((bits & 0x7F800000u) == 0x7F800000u && (bits & 0x007FFFFFu) != 0) {
    return static_cast<uint16_t>((bits >> 16) | 0x0040u);  // NaN stays a (quiet) NaN
  }
  const uint32_t rounding = 0x7FFFu + ((bits >> 16) & 1u);  // ties to even
  return static_cast<uint16_t>((bits + rounding) >> 16);
}

float RoundToBf16(float v) {
  const uint32_t bits = static_cast<uint32_t>(Bf16Bits(v)) << 16;
  float out;
  std::memcpy(&out, &bits, sizeof(out));
  return out;
}

namespace {

float FromBits(uint16_t h) {
  const uint32_t bits = static_cast<uint32_t>(h) << 16;
  float out;
  std::memcpy(&out, &bits, sizeof(out));
  return out;
}

}  // namespace

bool Bf16KernelBuilt() {
#ifdef MOTIONFORK_KERNELS_AVX512BF16
  return true;
#else
  return false;
#endif
}

bool Bf16KernelRuns() {
  static const bool runs = Bf16KernelBuilt() && Cpu().avx512_bf16;
  return runs;
}

PackedWeightBf16 PackWeightBf16(const float* w, int64_t rows, int64_t cols) {
  PackedWeightBf16 p;
  p.rows = rows;
  p.cols = cols;
  p.padded = (cols + 15) / 16 * 16;
  p.pairs = (rows + 1) / 2;
  p.data = AlignedFloats(p.pairs * p.padded);
  auto* out = reinterpret_cast<uint32_t*>(p.data.get());
  p.values = out;
  auto at = [&](int64_t k, int64_t c) -> uint32_t {
    return k < rows && c < cols ? Bf16Bits(w[k * cols + c]) : 0u;
  };
  for (int64_t c0 = 0; c0 < p.padded; c0 += kPanelColumns) {
    const int64_t width = std::min(kPanelColumns, p.padded - c0);
    for (int64_t q = 0; q < p.pairs; ++q) {
      for (int64_t j = 0; j < width; ++j)
        *out++ = at(2 * q, c0 + j) | (at(2 * q + 1, c0 + j) << 16);
    }
  }
  return p;
}

namespace portable {

void MatMulBf16(const float* x, int64_t m, int64_t ldx, const PackedWeightBf16& w, float* z) {
  for (int64_t r = 0; r < m; ++r) {
    float* zr = z + r * w.padded;
    std::fill(zr, zr + w.padded, 0.0f);
    const uint32_t* panel = w.values;
    for (int64_t c0 = 0; c0 < w.padded; c0 += kPanelColumns) {
      const int64_t width = std::min(kPanelColumns, w.padded - c0);
      for (int64_t q = 0; q < w.pairs; ++q) {
        const float a0 = RoundToBf16(x[r * ldx + 2 * q]);
        const float a1 = 2 * q + 1 < w.rows ? RoundToBf16(x[r * ldx + 2 * q + 1]) : 0.0f;
        const uint32_t* row = panel + q * width;
        for (int64_t j = 0; j < width; ++j) {
          zr[c0 + j] += a0 * FromBits(static_cast<uint16_t>(row[j] & 0xFFFFu)) +
                        a1 * FromBits(static_cast<uint16_t>(row[j] >> 16));
        }
      }
      panel += width * w.pairs;
    }
  }
}

}  // namespace portable

void MatMulBf16(const float* x, int64_t m, int64_t ldx, const PackedWeightBf16& w, float* z) {
#ifdef MOTIONFORK_KERNELS_AVX512BF16
  // UsePortableKernels(true) (backend.h) switches this kernel to the portable one too.
  if (Bf16KernelRuns() && ActiveBackend() == Backend::kAvx512)
    return avx512bf16::MatMulBf16(x, m, ldx, w, z);
#endif
  portable::MatMulBf16(x, m, ldx, w, z);
}

}  // namespace motionfork::kernels
