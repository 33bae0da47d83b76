// The AVX-512 backend of panel_product.h. Compiled with -march=skylake-avx512 (CMakeLists.txt)
// and only called when that backend runs (backend.h). Intrinsics and raw pointers only: no library
// templates are instantiated here, so no AVX-512 copy of a shared inline function can leak into
// other code.
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "generator/kernels/backends.h"

namespace motionfork::kernels::avx512 {
namespace {

#include "generator/kernels/tanh_avx512.inc"

// R rows of X times one panel of V * 16 columns of W: R * V accumulators stay in registers over
// all of K (8 x 48 measured fastest here: 11 loads per 24 multiply-adds).
template <int R, int V>
inline void Tile(const float* x, int64_t ldx, const float* panel, int64_t k_size, float* z,
                 int64_t ldz) {
  __m512 acc[R][V];
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r)
#pragma GCC unroll 3
    for (int v = 0; v < V; ++v) acc[r][v] = _mm512_setzero_ps();
  for (int64_t k = 0; k < k_size; ++k) {
    __m512 w[V];
#pragma GCC unroll 3
    for (int v = 0; v < V; ++v) w[v] = _mm512_load_ps(panel + (16 * V) * k + 16 * v);
#pragma GCC unroll 8
    for (int r = 0; r < R; ++r) {
      const __m512 b = _mm512_set1_ps(x[r * ldx + k]);
#pragma GCC unroll 3
      for (int v = 0; v < V; ++v) acc[r][v] = _mm512_fmadd_ps(b, w[v], acc[r][v]);
    }
  }
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r)
#pragma GCC unroll 3
    for (int v = 0; v < V; ++v) _mm512_store_ps(z + r * ldz + 16 * v, acc[r][v]);
}

constexpr int kTileRows = 8;

// Every panel of W for R rows.
template <int R>
void Rows(const float* x, int64_t ldx, const PackedWeight& w, float* z) {
  const float* panel = w.values;
  for (int64_t c = 0; c < w.padded; c += kPanelColumns) {
    const int64_t width = std::min<int64_t>(kPanelColumns, w.padded - c);
    switch (width / 16) {
      case 3:
        Tile<R, 3>(x, ldx, panel, w.rows, z + c, w.padded);
        break;
      case 2:
        Tile<R, 2>(x, ldx, panel, w.rows, z + c, w.padded);
        break;
      default:
        Tile<R, 1>(x, ldx, panel, w.rows, z + c, w.padded);
        break;
    }
    panel += width * w.rows;
  }
}

// Rows<r> for a tail of 1 <= r < kTileRows rows (Rows<kTileRows> for any other r).
void RowsTail(int r, const float* x, int64_t ldx, const PackedWeight& w, float* z) {
  using RowsKernel = void (*)(const float*, int64_t, const PackedWeight&, float*);
  static constexpr RowsKernel kTails[] = {Rows<1>, Rows<2>, Rows<3>, Rows<4>,
                                          Rows<5>, Rows<6>, Rows<7>};
  static_assert(sizeof(kTails) / sizeof(kTails[0]) == kTileRows - 1, "one kernel per tail length");
  (r >= 1 && r < kTileRows ? kTails[r - 1] : Rows<kTileRows>)(x, ldx, w, z);
}

// RN output rows (nodes rows[0..RN)) x V column vectors (16 floats each) from column c0: the
// mix over the N nodes as a small register-blocked product (A's entries broadcast, Z's rows
// loaded once per RN rows), then scale, shift, tanh and residual on the accumulators.
template <int RN, int V>
inline void MixTile(const LayerEpilogue& e, const int64_t* rows, const float* z, int64_t padded,
                    int64_t c0, int64_t width, const float* shared, const float* residual,
                    float* out, int64_t ld) {
  __m512 acc[RN][V];
#pragma GCC unroll 4
  for (int r = 0; r < RN; ++r) {
    const __m512 s = shared ? _mm512_set1_ps(e.rowsum[rows[r]]) : _mm512_setzero_ps();
#pragma GCC unroll 4
    for (int v = 0; v < V; ++v) {
      acc[r][v] =
          shared ? _mm512_mul_ps(s, _mm512_load_ps(shared + c0 + 16 * v)) : _mm512_setzero_ps();
    }
  }
  const float* a[RN];
#pragma GCC unroll 4
  for (int r = 0; r < RN; ++r) a[r] = e.adjacency + rows[r] * e.nodes;
  for (int64_t m = 0; m < e.nodes; ++m) {
    __m512 zv[V];
#pragma GCC unroll 4
    for (int v = 0; v < V; ++v) zv[v] = _mm512_load_ps(z + m * padded + c0 + 16 * v);
#pragma GCC unroll 4
    for (int r = 0; r < RN; ++r) {
      const __m512 am = _mm512_set1_ps(a[r][m]);
#pragma GCC unroll 4
      for (int v = 0; v < V; ++v) acc[r][v] = _mm512_fmadd_ps(am, zv[v], acc[r][v]);
    }
  }
#pragma GCC unroll 4
  for (int r = 0; r < RN; ++r) {
    const int64_t n = rows[r];
#pragma GCC unroll 4
    for (int v = 0; v < V; ++v) {
      const int64_t c = c0 + 16 * v;
      if (c >= width) break;
      const __m512 t = _mm512_load_ps(e.shift + n * padded + c);
      __m512 y = e.scale ? _mm512_fmadd_ps(acc[r][v], _mm512_load_ps(e.scale + n * padded + c), t)
                         : _mm512_add_ps(acc[r][v], t);
      if (e.tanh) y = Tanh16(y);
      const __mmask16 mask =
          width - c >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (width - c)) - 1);
      if (residual) y = _mm512_add_ps(y, _mm512_maskz_loadu_ps(mask, residual + n * ld + c));
      _mm512_mask_storeu_ps(out + n * ld + c, mask, y);
    }
  }
}

template <int RN>
inline void MixRowGroup(const LayerEpilogue& e, const int64_t* rows, const float* z, int64_t padded,
                        int64_t width, const float* shared, const float* residual, float* out,
                        int64_t ld) {
  int64_t c = 0;
  for (; c + 64 <= padded; c += 64)
    MixTile<RN, 4>(e, rows, z, padded, c, width, shared, residual, out, ld);
  if (c + 32 <= padded) {
    MixTile<RN, 2>(e, rows, z, padded, c, width, shared, residual, out, ld);
    c += 32;
  }
  if (c < padded) MixTile<RN, 1>(e, rows, z, padded, c, width, shared, residual, out, ld);
}

}  // namespace

void MatMul(const float* x, int64_t m, int64_t ldx, const PackedWeight& w, float* z) {
  int64_t r = 0;
  for (; r + kTileRows <= m; r += kTileRows) Rows<kTileRows>(x + r * ldx, ldx, w, z + r * w.padded);
  if (r < m) RowsTail(static_cast<int>(m - r), x + r * ldx, ldx, w, z + r * w.padded);
}

void MixRows(const LayerEpilogue& e, const float* z, int64_t padded, int64_t width,
             const float* shared, const int64_t* nodes, int64_t count, const float* residual,
             float* out, int64_t ld) {
  constexpr int kMixRows = 4;
  int64_t all[kMixRows];
  for (int64_t i = 0; i < count; i += kMixRows) {
    const int64_t* rows = nodes + i;
    if (!nodes) {
      for (int r = 0; r < kMixRows; ++r) all[r] = i + r;
      rows = all;
    }
    switch (count - i) {
      case 1:
        MixRowGroup<1>(e, rows, z, padded, width, shared, residual, out, ld);
        break;
      case 2:
        MixRowGroup<2>(e, rows, z, padded, width, shared, residual, out, ld);
        break;
      case 3:
        MixRowGroup<3>(e, rows, z, padded, width, shared, residual, out, ld);
        break;
      default:
        MixRowGroup<kMixRows>(e, rows, z, padded, width, shared, residual, out, ld);
        break;
    }
  }
}

}  // namespace motionfork::kernels::avx512
