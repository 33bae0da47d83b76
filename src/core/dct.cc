#include "core/dct.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace motionfork {

Eigen::MatrixXd DctMatrix(int num_frames) {
  if (num_frames < 1) {
    throw std::invalid_argument("DctMatrix: expected at least 1 frame, got " +
                                std::to_string(num_frames));
  }
  const int N = num_frames;
  Eigen::MatrixXd d(N, N);
  for (int l = 0; l < N; ++l) {
    const double scale = std::sqrt(2.0 / N) / (l == 0 ? std::sqrt(2.0) : 1.0);
    for (int n = 0; n < N; ++n) d(l, n) = scale * std::cos(M_PI / (2.0 * N) * (2 * n + 1) * l);
  }
  return d;
}

Eigen::MatrixXf Dct(const Eigen::MatrixXf& x, int num_coeffs) {
  const int T = static_cast<int>(x.rows());
  if (num_coeffs < 1 || num_coeffs > T) {
    throw std::invalid_argument("Dct: expected 1 <= num_coeffs <= " + std::to_string(T) +
                                " (frames), got " + std::to_string(num_coeffs));
  }
  const Eigen::MatrixXd d = DctMatrix(T).topRows(num_coeffs);
  return (d * x.cast<double>()).cast<float>();
}

Eigen::MatrixXf InverseDct(const Eigen::MatrixXf& coeffs, int num_frames) {
  const int n = static_cast<int>(coeffs.rows());
  if (n < 1 || n > num_frames) {
    throw std::invalid_argument("InverseDct: expected 1 <= coefficients <= " +
                                std::to_string(num_frames) + " (frames), got " + std::to_string(n));
  }
  const Eigen::MatrixXd d = DctMatrix(num_frames).topRows(n);
  return (d.transpose() * coeffs.cast<double>()).cast<float>();
}

}  // namespace motionfork
