// The AVX512-BF16 kernel of bf16_product.h. Compiled with -march=cooperlake (CMakeLists.txt) and
// only called where the CPU has AVX512-BF16 (Bf16KernelRuns). Intrinsics and raw pointers only, as
// in panel_product_avx512.cc: no library template gets an AVX-512 copy here.
#include <immintrin.h>

#include <cstdint>

#include "generator/kernels/backends.h"

namespace motionfork::kernels::avx512bf16 {
namespace {

constexpr int kTileRows = 8;
constexpr int64_t kChunkPairs = 512;  // X rows converted 1,024 values at a time (stack buffer)

// Values k0 .. k1 - 1 of R rows of X rounded to bf16 (ties to even), one 32-bit word per pair,
// a zero high half padding an odd count; row r's words at out + r * kChunkPairs.
template <int R>
inline void ConvertRows(const float* x, int64_t ldx, int64_t k0, int64_t k1, uint32_t* out) {
  const int64_t n = k1 - k0;
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r) {
    const float* row = x + r * ldx + k0;
    auto* o = reinterpret_cast<uint16_t*>(out + r * kChunkPairs);
    int64_t i = 0;
    for (; i + 16 <= n; i += 16) {
      const __m256bh h = _mm512_cvtneps_pbh(_mm512_loadu_ps(row + i));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(o + i), reinterpret_cast<const __m256i&>(h));
    }
    if (i < n) {
      const __mmask16 mask = static_cast<__mmask16>((1u << (n - i)) - 1);
      const __m256bh h = _mm512_cvtneps_pbh(_mm512_maskz_loadu_ps(mask, row + i));
      _mm256_mask_storeu_epi16(o + i, mask, reinterpret_cast<const __m256i&>(h));
    }
    if (n % 2) o[n] = 0;
  }
}

// R rows times one panel of V * 16 columns over `pairs` pairs of K: R * V float accumulators in
// registers, two multiply-adds per lane and instruction; `add`: onto what z holds.
template <int R, int V>
inline void Tile(const uint32_t* xb, const uint32_t* panel, int64_t pairs, float* z, int64_t ldz,
                 bool add) {
  __m512 acc[R][V];
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r)
#pragma GCC unroll 3
    for (int v = 0; v < V; ++v)
      acc[r][v] = add ? _mm512_load_ps(z + r * ldz + 16 * v) : _mm512_setzero_ps();
  for (int64_t q = 0; q < pairs; ++q) {
    __m512i w[V];
#pragma GCC unroll 3
    for (int v = 0; v < V; ++v) w[v] = _mm512_load_si512(panel + (16 * V) * q + 16 * v);
#pragma GCC unroll 8
    for (int r = 0; r < R; ++r) {
      const __m512i b = _mm512_set1_epi32(static_cast<int>(xb[r * kChunkPairs + q]));
#pragma GCC unroll 3
      for (int v = 0; v < V; ++v) {
        acc[r][v] = _mm512_dpbf16_ps(acc[r][v], reinterpret_cast<const __m512bh&>(b),
                                     reinterpret_cast<const __m512bh&>(w[v]));
      }
    }
  }
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r)
#pragma GCC unroll 3
    for (int v = 0; v < V; ++v) _mm512_store_ps(z + r * ldz + 16 * v, acc[r][v]);
}

// Every panel of W for R rows, K in chunks of kChunkPairs pairs.
template <int R>
void Rows(const float* x, int64_t ldx, const PackedWeightBf16& w, float* z) {
  alignas(64) uint32_t xb[R * kChunkPairs];
  for (int64_t q0 = 0; q0 < w.pairs; q0 += kChunkPairs) {
    const int64_t pairs = w.pairs - q0 < kChunkPairs ? w.pairs - q0 : kChunkPairs;
    const int64_t k1 = 2 * (q0 + pairs) < w.rows ? 2 * (q0 + pairs) : w.rows;
    ConvertRows<R>(x, ldx, 2 * q0, k1, xb);
    const uint32_t* panel = w.values;
    for (int64_t c = 0; c < w.padded; c += kPanelColumns) {
      const int64_t width = w.padded - c < kPanelColumns ? w.padded - c : kPanelColumns;
      const uint32_t* from = panel + q0 * width;
      switch (width / 16) {
        case 3:
          Tile<R, 3>(xb, from, pairs, z + c, w.padded, q0 > 0);
          break;
        case 2:
          Tile<R, 2>(xb, from, pairs, z + c, w.padded, q0 > 0);
          break;
        default:
          Tile<R, 1>(xb, from, pairs, z + c, w.padded, q0 > 0);
          break;
      }
      panel += width * w.pairs;
    }
  }
}

void RowsTail(int r, const float* x, int64_t ldx, const PackedWeightBf16& w, float* z) {
  using RowsKernel = void (*)(const float*, int64_t, const PackedWeightBf16&, float*);
  static constexpr RowsKernel kTails[] = {Rows<1>, Rows<2>, Rows<3>, Rows<4>,
                                          Rows<5>, Rows<6>, Rows<7>};
  static_assert(sizeof(kTails) / sizeof(kTails[0]) == kTileRows - 1, "one kernel per tail length");
  (r >= 1 && r < kTileRows ? kTails[r - 1] : Rows<kTileRows>)(x, ldx, w, z);
}

}  // namespace

void MatMulBf16(const float* x, int64_t m, int64_t ldx, const PackedWeightBf16& w, float* z) {
  int64_t r = 0;
  for (; r + kTileRows <= m; r += kTileRows) Rows<kTileRows>(x + r * ldx, ldx, w, z + r * w.padded);
  if (r < m) RowsTail(static_cast<int>(m - r), x + r * ldx, ldx, w, z + r * w.padded);
}

}  // namespace motionfork::kernels::avx512bf16
