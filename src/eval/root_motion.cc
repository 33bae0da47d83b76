#include "eval/root_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace motionfork {
namespace {

double Height(const float* p, UpAxis up) { return up.sign * static_cast<double>(p[up.axis]); }

void RequireFeet(const std::vector<int>& feet, int J) {
  if (feet.empty()) throw std::invalid_argument("root motion: no feet given");
  for (int f : feet) {
    if (f < 0 || f >= J) {
      throw std::invalid_argument("root motion: foot joint " + std::to_string(f) +
                                  " out of range, expected 0-" + std::to_string(J - 1));
    }
  }
}

}  // namespace

RootFigures& RootFigures::operator+=(const RootFigures& o) {
  ade += o.ade;
  fde += o.fde;
  final_spread += o.final_spread;
  skating += o.skating;
  truth_skating += o.truth_skating;
  return *this;
}

RootFigures RootFigures::operator/(double n) const {
  return {ade / n, fde / n, final_spread / n, skating / n, truth_skating / n};
}

Displacement RootMinDisplacement(const float* samples, int K, int T, int J,
                                 const float* truth_root) {
  if (K < 1 || T < 1 || J < 1) {
    throw std::invalid_argument("root motion: K, T and J must be >= 1, got " + std::to_string(K) +
                                ", " + std::to_string(T) + ", " + std::to_string(J));
  }
  Displacement best{std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};
  for (int k = 0; k < K; ++k) {
    double sum = 0, last = 0;
    for (int t = 0; t < T; ++t) {
      const float* r = samples + (static_cast<size_t>(k) * T + t) * J * 3;
      const float* g = truth_root + static_cast<size_t>(t) * 3;
      last = std::sqrt(std::pow(r[0] - g[0], 2.0) + std::pow(r[1] - g[1], 2.0) +
                       std::pow(r[2] - g[2], 2.0));
      sum += last;
    }
    best.ade = std::min(best.ade, sum / T);
    best.fde = std::min(best.fde, last);
  }
  return best;
}

double FinalRootSpread(const float* samples, int K, int T, int J, UpAxis up) {
  if (K < 2)
    throw std::invalid_argument("root motion: the spread needs K >= 2, got " + std::to_string(K));
  const auto [a, b] = GroundAxes(up);
  double sum = 0;
  for (int i = 0; i < K; ++i) {
    const float* p = samples + (static_cast<size_t>(i) * T + T - 1) * J * 3;
    for (int j = i + 1; j < K; ++j) {
      const float* q = samples + (static_cast<size_t>(j) * T + T - 1) * J * 3;
      sum += std::hypot(static_cast<double>(p[a]) - q[a], static_cast<double>(p[b]) - q[b]);
    }
  }
  return sum / (K * (K - 1) / 2.0);
}

double FootSkating(const float* frames, int T, int J, const std::vector<int>& feet, UpAxis up,
                   double ground, double contact_height) {
  if (T < 2)
    throw std::invalid_argument("root motion: skating needs 2 frames, got " + std::to_string(T));
  if (!(contact_height > 0)) {
    throw std::invalid_argument("root motion: contact height must be > 0");
  }
  RequireFeet(feet, J);
  const auto [a, b] = GroundAxes(up);
  double sum = 0;
  for (int t = 1; t < T; ++t) {
    for (int f : feet) {
      const float* p = frames + (static_cast<size_t>(t - 1) * J + f) * 3;
      const float* q = frames + (static_cast<size_t>(t) * J + f) * 3;
      const double h = std::max(Height(p, up), Height(q, up)) - ground;
      if (h >= contact_height) continue;
      const double weight = 2.0 - std::pow(2.0, std::max(h, 0.0) / contact_height);
      sum +=
          weight * std::hypot(static_cast<double>(q[a]) - p[a], static_cast<double>(q[b]) - p[b]);
    }
  }
  return sum / (T - 1);
}

double GroundHeight(const float* frames, int T, int J, const std::vector<int>& feet, UpAxis up) {
  if (T < 1) throw std::invalid_argument("root motion: no frames");
  RequireFeet(feet, J);
  GroundAxes(up);
  double low = std::numeric_limits<double>::infinity();
  for (int t = 0; t < T; ++t) {
    for (int f : feet)
      low = std::min(low, Height(frames + (static_cast<size_t>(t) * J + f) * 3, up));
  }
  return low;
}

}  // namespace motionfork
