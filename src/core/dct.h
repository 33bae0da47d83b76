// Orthonormal DCT-II along time, as in the HG-VAE paper (appendix A, eq. 6):
//   C[l] = sqrt(2/N) * sum_n x[n] * 1/sqrt(1 + delta(l,0)) * cos(pi/(2N) * (2n+1) * l)
// with 0-based n, l. The N x N matrix D is orthogonal, so the inverse is D^T; keeping only the
// first n rows gives the truncated (low-pass) transform used by the generator.
#pragma once

#include <Eigen/Core>

namespace motionfork {

// D: [N, N] in double; row l holds coefficient l. Throws std::invalid_argument for N < 1.
Eigen::MatrixXd DctMatrix(int num_frames);

// Forward transform of a trajectory block x: [T, D] (T frames, D channels, e.g. J*3), returning
// the first num_coeffs coefficients: [num_coeffs, D]. num_coeffs in 1..T.
Eigen::MatrixXf Dct(const Eigen::MatrixXf& x, int num_coeffs);

// Inverse transform of the first n coefficients c: [n, D] back to num_frames frames: [T, D]
// (missing high frequencies are taken as zero). n <= num_frames.
Eigen::MatrixXf InverseDct(const Eigen::MatrixXf& coeffs, int num_frames);

}  // namespace motionfork
