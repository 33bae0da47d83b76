// The portable backend of panel_product.h: the AVX-512 backend's loops in plain C++ (the compiler
// vectorises the inner loops over columns at the default flags). Each output element is the same
// sequence of multiply-adds as there, so a row still does not depend on the rows around it.
#include <algorithm>
#include <cstdint>

#include "generator/kernels/backends.h"

namespace motionfork::kernels::portable {

namespace {

// One row of X times one panel of W (width W columns, stored [K][W]): W accumulators.
template <int W>
void RowPanel(const float* x, const float* panel, int64_t k_size, float* z) {
  float acc[W] = {};
  for (int64_t k = 0; k < k_size; ++k) {
    const float xk = x[k];
    const float* wk = panel + W * k;
    for (int j = 0; j < W; ++j) acc[j] += xk * wk[j];
  }
  for (int j = 0; j < W; ++j) z[j] = acc[j];
}

// Columns per step of MixRows: its accumulators stay in registers or L1.
constexpr int64_t kMixColumns = 64;

}  // namespace

void MatMul(const float* x, int64_t m, int64_t ldx, const PackedWeight& w, float* z) {
  for (int64_t r = 0; r < m; ++r) {
    const float* panel = w.values;
    for (int64_t c = 0; c < w.padded; c += kPanelColumns) {
      const int64_t width = std::min<int64_t>(kPanelColumns, w.padded - c);
      float* out = z + r * w.padded + c;
      switch (width / 16) {
        case 3:
          RowPanel<48>(x + r * ldx, panel, w.rows, out);
          break;
        case 2:
          RowPanel<32>(x + r * ldx, panel, w.rows, out);
          break;
        default:
          RowPanel<16>(x + r * ldx, panel, w.rows, out);
          break;
      }
      panel += width * w.rows;
    }
  }
}

void MixRows(const LayerEpilogue& e, const float* z, int64_t padded, int64_t width,
             const float* shared, const int64_t* nodes, int64_t count, const float* residual,
             float* out, int64_t ld) {
  float acc[kMixColumns];
  for (int64_t i = 0; i < count; ++i) {
    const int64_t n = nodes ? nodes[i] : i;
    const float* a = e.adjacency + n * e.nodes;
    for (int64_t c0 = 0; c0 < width; c0 += kMixColumns) {
      const int64_t cw = std::min(kMixColumns, width - c0);
      const float s = shared ? e.rowsum[n] : 0.0f;
      for (int64_t j = 0; j < cw; ++j) acc[j] = shared ? s * shared[c0 + j] : 0.0f;
      for (int64_t m = 0; m < e.nodes; ++m) {
        const float am = a[m];
        const float* zm = z + m * padded + c0;
        for (int64_t j = 0; j < cw; ++j) acc[j] += am * zm[j];
      }
      const float* shift = e.shift + n * padded + c0;
      if (e.scale) {
        const float* scale = e.scale + n * padded + c0;
        for (int64_t j = 0; j < cw; ++j) acc[j] = acc[j] * scale[j] + shift[j];
      } else {
        for (int64_t j = 0; j < cw; ++j) acc[j] += shift[j];
      }
      if (e.tanh) Tanh(acc, cw);
      float* o = out + n * ld + c0;
      if (residual) {
        const float* res = residual + n * ld + c0;  // may be o itself: read before written
        for (int64_t j = 0; j < cw; ++j) o[j] = acc[j] + res[j];
      } else {
        for (int64_t j = 0; j < cw; ++j) o[j] = acc[j];
      }
    }
  }
}

}  // namespace motionfork::kernels::portable
