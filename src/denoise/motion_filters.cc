#include "denoise/motion_filters.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace motionfork {
namespace {

constexpr double kPi = 3.14159265358979323846;

int CheckedFrames(const std::vector<float>& p, int joints, const char* what) {
  const size_t F = static_cast<size_t>(std::max(joints, 0)) * 3;
  if (joints < 1 || p.size() % F != 0) {
    throw std::invalid_argument(std::string(what) + ": expected frames x " +
                                std::to_string(joints) + " joints x 3 values, got " +
                                std::to_string(p.size()));
  }
  return static_cast<int>(p.size() / F);
}

// Weights w[k], k = -before..after, with sum_k w[k] y[t + k] = the least-squares polynomial of
// degree `order` through those frames, evaluated at the centre.
std::vector<double> SavitzkyGolayWeights(int before, int after, int order) {
  const int n = before + after + 1, degree = std::min(order, n - 1);
  Eigen::MatrixXd V(n, degree + 1);
  for (int i = 0; i < n; ++i) {
    const double k = i - before;
    double power = 1;
    for (int m = 0; m <= degree; ++m, power *= k) V(i, m) = power;
  }
  // First row of the pseudo-inverse: the constant term of the fit.
  const Eigen::MatrixXd pinv = V.completeOrthogonalDecomposition().pseudoInverse();
  std::vector<double> w(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) w[static_cast<size_t>(i)] = pinv(0, i);
  return w;
}

}  // namespace

std::vector<float> SavitzkyGolay(const std::vector<float>& p, int joints, int half_window,
                                 int order) {
  const int T = CheckedFrames(p, joints, "SavitzkyGolay");
  if (half_window < 1 || order < 0) {
    throw std::invalid_argument("SavitzkyGolay: expected half_window >= 1 and order >= 0, got " +
                                std::to_string(half_window) + " and " + std::to_string(order));
  }
  const int F = joints * 3;
  std::map<std::pair<int, int>, std::vector<double>> weights;  // (before, after) -> weights
  std::vector<float> out(p.size());
  for (int t = 0; t < T; ++t) {
    const int before = std::min(half_window, t), after = std::min(half_window, T - 1 - t);
    auto it = weights.find({before, after});
    if (it == weights.end())
      it =
          weights.emplace(std::make_pair(before, after), SavitzkyGolayWeights(before, after, order))
              .first;
    const std::vector<double>& w = it->second;
    for (int v = 0; v < F; ++v) {
      double s = 0;
      for (int k = -before; k <= after; ++k)
        s += w[static_cast<size_t>(k + before)] * p[static_cast<size_t>(t + k) * F + v];
      out[static_cast<size_t>(t) * F + v] = static_cast<float>(s);
    }
  }
  return out;
}

std::vector<float> OneEuroFilter(const std::vector<float>& p, int joints, double fps,
                                 double min_cutoff, double beta, double d_cutoff) {
  const int T = CheckedFrames(p, joints, "OneEuroFilter");
  if (!(fps > 0) || !(min_cutoff > 0) || !(d_cutoff > 0) || !(beta >= 0)) {
    throw std::invalid_argument(
        "OneEuroFilter: expected fps, min_cutoff and d_cutoff > 0 and beta >= 0");
  }
  const int F = joints * 3;
  const double dt = 1.0 / fps;
  // Smoothing factor of a first-order low-pass filter at `cutoff` Hz.
  auto alpha = [dt](double cutoff) {
    const double tau = 1.0 / (2 * kPi * cutoff);
    return 1.0 / (1.0 + tau / dt);
  };
  const double a_d = alpha(d_cutoff);
  std::vector<float> out(p.size());
  for (int v = 0; v < F; ++v) {
    double x_hat = p[static_cast<size_t>(v)], dx_hat = 0;
    out[static_cast<size_t>(v)] = static_cast<float>(x_hat);
    for (int t = 1; t < T; ++t) {
      const double x = p[static_cast<size_t>(t) * F + v];
      dx_hat += a_d * ((x - x_hat) / dt - dx_hat);
      x_hat += alpha(min_cutoff + beta * std::abs(dx_hat)) * (x - x_hat);
      out[static_cast<size_t>(t) * F + v] = static_cast<float>(x_hat);
    }
  }
  return out;
}

double MedianInPlace(std::vector<double>* v) {
  if (v->empty()) throw std::invalid_argument("MedianInPlace: no values");
  const size_t n = v->size(), mid = n / 2;
  std::nth_element(v->begin(), v->begin() + mid, v->end());
  const double upper = (*v)[mid];
  if (n % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(v->begin(), v->begin() + mid));
}

std::vector<uint8_t> HampelOutliers(const std::vector<float>& p, int joints, int half_window,
                                    double n_sigma, std::vector<float>* medians) {
  const int T = CheckedFrames(p, joints, "HampelOutliers");
  if (half_window < 1 || !(n_sigma >= 0)) {
    throw std::invalid_argument("HampelOutliers: expected half_window >= 1 and n_sigma >= 0, got " +
                                std::to_string(half_window) + " and " + std::to_string(n_sigma));
  }
  const int F = joints * 3;
  std::vector<uint8_t> flags(p.size(), 0);
  medians->assign(p.size(), 0.0f);
  std::vector<double> window, deviation;
  for (int v = 0; v < F; ++v) {
    for (int t = 0; t < T; ++t) {
      const int a = std::max(0, t - half_window), b = std::min(T - 1, t + half_window);
      window.clear();
      for (int k = a; k <= b; ++k) window.push_back(p[static_cast<size_t>(k) * F + v]);
      deviation = window;
      const double m = MedianInPlace(&window);
      for (double& d : deviation) d = std::abs(d - m);
      const double scale = 1.4826 * MedianInPlace(&deviation);
      const size_t i = static_cast<size_t>(t) * F + v;
      (*medians)[i] = static_cast<float>(m);
      flags[i] = std::abs(p[i] - m) > n_sigma * scale ? 1 : 0;
    }
  }
  return flags;
}

std::vector<float> HampelFilter(const std::vector<float>& p, int joints, int half_window,
                                double n_sigma) {
  std::vector<float> medians;
  const std::vector<uint8_t> flags = HampelOutliers(p, joints, half_window, n_sigma, &medians);
  std::vector<float> out = p;
  for (size_t i = 0; i < out.size(); ++i)
    if (flags[i]) out[i] = medians[i];
  return out;
}

}  // namespace motionfork
