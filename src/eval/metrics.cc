#include "eval/metrics.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace motionfork {
namespace {

void CheckShape(const char* what, int K, int min_k, int T, int D) {
  if (K < min_k) {
    throw std::invalid_argument(
        std::string(what) + ": expected K >= " + std::to_string(min_k) +
        (min_k == 2 ? " samples (APD is a mean over pairs of samples)" : " samples") + ", got " +
        std::to_string(K));
  }
  if (T < 1 || D < 1) {
    throw std::invalid_argument(std::string(what) + ": expected T >= 1 frames and D >= 1, got T " +
                                std::to_string(T) + ", D " + std::to_string(D));
  }
}

// Squared distances (m^2) below which DisplacementWorkspace recomputes a distance directly.
constexpr float kExactBelow = 1e-4f;

}  // namespace

double Apd(const float* samples, int K, int T, int D) {
  CheckShape("APD", K, 2, T, D);
  const Eigen::Index n = static_cast<Eigen::Index>(T) * D;
  using Rows =
      Eigen::Map<const Eigen::Array<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
  const Rows x(samples, K, n);
  double total = 0;
  for (int i = 0; i < K; ++i) {
    for (int j = i + 1; j < K; ++j) {
      // Float differences (exact zero for identical samples), one float sum per frame, frames
      // summed in double: relative error ~1e-7.
      double d2 = 0;
      for (int t = 0; t < T; ++t) {
        d2 += (x.row(i).segment(t * D, D) - x.row(j).segment(t * D, D)).square().sum();
      }
      total += std::sqrt(d2);
    }
  }
  // Each unordered pair stands for two ordered ones: the means agree.
  return total / (0.5 * K * (K - 1));
}

double ApdOfDims(const float* samples, int K, int T, int D, const std::vector<int>& dims) {
  CheckShape("APD", K, 2, T, D);
  for (int d : dims) {
    if (d < 0 || d >= D) {
      throw std::invalid_argument("APD of dims: expected dims in [0, " + std::to_string(D) +
                                  "), got " + std::to_string(d));
    }
  }
  const size_t n = static_cast<size_t>(T) * D;
  double total = 0;
  for (int i = 0; i < K; ++i) {
    for (int j = i + 1; j < K; ++j) {
      double d2 = 0;
      for (int t = 0; t < T; ++t) {
        const float* a = samples + i * n + static_cast<size_t>(t) * D;
        const float* b = samples + j * n + static_cast<size_t>(t) * D;
        for (int d : dims) {
          const double v = double(a[d]) - double(b[d]);
          d2 += v * v;
        }
      }
      total += std::sqrt(d2);
    }
  }
  return total / (0.5 * K * (K - 1));
}

Displacement MinDisplacement(const float* samples, int K, int T, int D, const float* truth) {
  CheckShape("ADE/FDE", K, 1, T, D);
  Displacement best{std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};
  for (int k = 0; k < K; ++k) {
    double sum = 0, last = 0;
    for (int t = 0; t < T; ++t) {
      const float* s = samples + (static_cast<size_t>(k) * T + t) * D;
      const float* g = truth + static_cast<size_t>(t) * D;
      double d2 = 0;
      for (int e = 0; e < D; ++e) {
        const double d = double(s[e]) - double(g[e]);
        d2 += d * d;
      }
      last = std::sqrt(d2);
      sum += last;
    }
    best.ade = std::min(best.ade, sum / T);
    best.fde = std::min(best.fde, last);
  }
  return best;
}

Displacement MeanMinDisplacement(const std::vector<float>& predictions,
                                 const std::vector<float>& futures, int H, int K, int T, int D) {
  const size_t per_future = static_cast<size_t>(T) * D;
  if (H < 1 || predictions.size() != static_cast<size_t>(H) * K * per_future ||
      futures.size() != static_cast<size_t>(H) * per_future) {
    throw std::invalid_argument("MeanMinDisplacement: expected predictions [" + std::to_string(H) +
                                ", " + std::to_string(K) + ", " + std::to_string(T) + ", " +
                                std::to_string(D) + "] and futures [" + std::to_string(H) + ", " +
                                std::to_string(T) + ", " + std::to_string(D) + "], got " +
                                std::to_string(predictions.size()) + " and " +
                                std::to_string(futures.size()) + " values");
  }
  Displacement mean;
  for (int h = 0; h < H; ++h) {
    const Displacement d = MinDisplacement(predictions.data() + h * K * per_future, K, T, D,
                                           futures.data() + h * per_future);
    mean.ade += d.ade;
    mean.fde += d.fde;
  }
  mean.ade /= H;
  mean.fde /= H;
  return mean;
}

void DisplacementWorkspace::Run(const float* samples, int K, int T, int D,
                                const std::vector<const float*>& truths,
                                std::vector<Displacement>* out) {
  CheckShape("ADE/FDE", K, 1, T, D);
  const int M = static_cast<int>(truths.size());
  out->assign(M, Displacement{});
  if (M == 0) return;
  using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using Arr = Eigen::Array<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using Vec = Eigen::Map<const Eigen::ArrayXf>;
  // Frame-major copies, centred on sample 0's pose of the frame: distances do not change, the
  // vectors shrink to the spread between poses, so |s|^2 + |g|^2 - 2 s.g loses few digits.
  samples_.resize(static_cast<size_t>(T) * K * D);
  sample_sq_.resize(static_cast<size_t>(T) * K);
  truths_.resize(static_cast<size_t>(T) * M * D);
  truth_sq_.resize(static_cast<size_t>(T) * M);
  for (int t = 0; t < T; ++t) {
    const Vec centre(samples + static_cast<size_t>(t) * D, D);
    for (int k = 0; k < K; ++k) {
      Eigen::Map<Eigen::ArrayXf> o(samples_.data() + (static_cast<size_t>(t) * K + k) * D, D);
      o = Vec(samples + (static_cast<size_t>(k) * T + t) * D, D) - centre;
      sample_sq_[static_cast<size_t>(t) * K + k] = o.square().sum();
    }
    for (int m = 0; m < M; ++m) {
      Eigen::Map<Eigen::ArrayXf> o(truths_.data() + (static_cast<size_t>(t) * M + m) * D, D);
      o = Vec(truths[m] + static_cast<size_t>(t) * D, D) - centre;
      truth_sq_[static_cast<size_t>(t) * M + m] = o.square().sum();
    }
  }
  cross_.resize(static_cast<size_t>(K) * M);
  sum_.assign(static_cast<size_t>(K) * M, 0.0f);
  Eigen::Map<RowMajor> cross(cross_.data(), K, M);
  Eigen::Map<Arr> d(cross_.data(), K, M);
  Eigen::Map<Arr> sum(sum_.data(), K, M);
  for (int t = 0; t < T; ++t) {
    const Eigen::Map<const RowMajor> s(samples_.data() + static_cast<size_t>(t) * K * D, K, D);
    const Eigen::Map<const RowMajor> g(truths_.data() + static_cast<size_t>(t) * M * D, M, D);
    const Eigen::Map<const Eigen::ArrayXf> ss(sample_sq_.data() + static_cast<size_t>(t) * K, K);
    const Eigen::Map<const Eigen::RowVectorXf> gs(truth_sq_.data() + static_cast<size_t>(t) * M, M);
    cross.noalias() = s * g.transpose();
    // Squared distances [K, M].
    d = -2.0f * cross.array();
    d.rowwise() += gs.array();
    d.colwise() += ss;
    // Near zero the expansion's rounding (~1e-7 m^2) matters: recompute those exactly.
    if (d.minCoeff() < kExactBelow) {
      for (int k = 0; k < K; ++k) {
        for (int m = 0; m < M; ++m) {
          if (d(k, m) >= kExactBelow) continue;
          const Vec a(samples + (static_cast<size_t>(k) * T + t) * D, D);
          const Vec b(truths[m] + static_cast<size_t>(t) * D, D);
          d(k, m) = (a - b).square().sum();
        }
      }
    }
    d = d.sqrt();
    sum += d;
  }
  // d holds the last frame's distances.
  for (int m = 0; m < M; ++m) {
    const double ade = sum.col(m).minCoeff() / double(T);
    const double fde = d.col(m).minCoeff();
    (*out)[m] = Displacement{ade, fde};
  }
}

WindowMetrics& operator+=(WindowMetrics& sum, const WindowMetrics& m) {
  sum.apd += m.apd;
  sum.ade += m.ade;
  sum.fde += m.fde;
  sum.mmade += m.mmade;
  sum.mmfde += m.mmfde;
  return sum;
}

WindowMetrics operator/(WindowMetrics sum, double n) {
  sum.apd /= n;
  sum.ade /= n;
  sum.fde /= n;
  sum.mmade /= n;
  sum.mmfde /= n;
  return sum;
}

}  // namespace motionfork
