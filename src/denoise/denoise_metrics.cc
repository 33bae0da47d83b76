#include "denoise/denoise_metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace motionfork {

double MeanJointError(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size() || a.empty() || a.size() % 3 != 0) {
    throw std::invalid_argument("MeanJointError: expected two sequences of the same non-zero size");
  }
  double sum = 0;
  for (size_t i = 0; i < a.size(); i += 3) {
    const double dx = a[i] - b[i], dy = a[i + 1] - b[i + 1], dz = a[i + 2] - b[i + 2];
    sum += std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  return sum / static_cast<double>(a.size() / 3);
}

double MeanAcceleration(const std::vector<float>& p, int joints, double fps) {
  const size_t F = static_cast<size_t>(joints) * 3, T = p.size() / F;
  if (T < 3) return 0;
  double sum = 0;
  for (size_t t = 1; t + 1 < T; ++t) {
    for (size_t j = 0; j < F; j += 3) {
      double s = 0;
      for (size_t d = 0; d < 3; ++d) {
        const double a = p[(t + 1) * F + j + d] - 2.0 * p[t * F + j + d] + p[(t - 1) * F + j + d];
        s += a * a;
      }
      sum += std::sqrt(s);
    }
  }
  return sum / static_cast<double>((T - 2) * joints) * fps * fps;
}

std::vector<float> GaussianSmooth(const std::vector<float>& p, int joints, double sigma) {
  const int F = joints * 3, T = static_cast<int>(p.size() / F);
  const int radius = std::max(1, static_cast<int>(std::ceil(3 * sigma)));
  std::vector<double> kernel(2 * radius + 1);
  for (int k = -radius; k <= radius; ++k)
    kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  std::vector<float> out(p.size());
  for (int t = 0; t < T; ++t) {
    for (int v = 0; v < F; ++v) {
      double s = 0, w = 0;
      for (int k = std::max(-radius, -t); k <= std::min(radius, T - 1 - t); ++k) {
        s += kernel[k + radius] * p[static_cast<size_t>(t + k) * F + v];
        w += kernel[k + radius];
      }
      out[static_cast<size_t>(t) * F + v] = static_cast<float>(s / w);
    }
  }
  return out;
}

}  // namespace motionfork
