// Vectorised tanh kernels (Eigen's rational approximation, within 3e-7 of std::tanh), dispatched
// at run time to an AVX2/FMA build when the CPU has it. Debian's LibTorch evaluates tanh about
// five times slower, and the generator applies it to every hidden feature of every layer.
#pragma once

#include <cstdint>

namespace motionfork::fast {

// x[i] = tanh(x[i]) for i < n.
void Tanh(float* x, int64_t n);

// For rows r < rows of width `width`: x[r, :] = tanh(x[r, :] * scale[row_group(r), :] +
// shift[row_group(r), :]) where row_group(r) = r / rows_per_group. Shapes: x [rows, width],
// scale and shift [rows / rows_per_group, width]. (Node-major layout: a group is a node.)
void ScaleShiftTanh(float* x, const float* scale, const float* shift, int64_t rows,
                    int64_t rows_per_group, int64_t width);

}  // namespace motionfork::fast
