// The one tanh of the generator (LibTorch paths, fused autograd ops and fused inference alike):
// tanh(x) = 1 - 2 / (exp(2x) + 1) with exp by a degree-5 polynomial, within 3e-7 of std::tanh,
// NaN kept (backends: tanh_avx512.inc, tanh_portable.cc). Debian's LibTorch evaluates tanh about
// five times slower, and the generator applies it to every hidden feature of every layer.
#pragma once

#include <cstdint>

namespace motionfork::kernels {

// x[i] = tanh(x[i]) for i < n.
void Tanh(float* x, int64_t n);

// For rows r < rows of width `width`: x[r, :] = tanh(x[r, :] * scale[row_group(r), :] +
// shift[row_group(r), :]) where row_group(r) = r / rows_per_group. Shapes: x [rows, width],
// scale and shift [rows / rows_per_group, width]. (Node-major layout: a group is a node.)
void ScaleShiftTanh(float* x, const float* scale, const float* shift, int64_t rows,
                    int64_t rows_per_group, int64_t width);

}  // namespace motionfork::kernels
