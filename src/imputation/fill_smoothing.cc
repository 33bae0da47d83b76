#include "imputation/fill_smoothing.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace motionfork {
namespace {

// Solves the symmetric positive definite pentadiagonal system A x = b in place (A as its diagonal
// and two upper bands: band[t] = {A(t,t), A(t,t+1), A(t,t+2)}) by an LDL^T factorisation.
void SolvePentadiagonal(std::vector<std::array<double, 3>>* band, std::vector<double>* b) {
  auto& a = *band;
  std::vector<double>& x = *b;
  const size_t T = a.size();
  // L has unit diagonal and two lower bands l1(t) = L(t, t-1), l2(t) = L(t, t-2).
  std::vector<double> d(T), l1(T, 0.0), l2(T, 0.0);
  for (size_t t = 0; t < T; ++t) {
    if (t >= 2) l2[t] = a[t - 2][2] / d[t - 2];
    if (t >= 1) {
      double v = a[t - 1][1];
      if (t >= 2) v -= l2[t] * d[t - 2] * l1[t - 1];
      l1[t] = v / d[t - 1];
    }
    double v = a[t][0];
    if (t >= 1) v -= l1[t] * l1[t] * d[t - 1];
    if (t >= 2) v -= l2[t] * l2[t] * d[t - 2];
    d[t] = v;
  }
  for (size_t t = 0; t < T; ++t) {  // L y = b
    if (t >= 1) x[t] -= l1[t] * x[t - 1];
    if (t >= 2) x[t] -= l2[t] * x[t - 2];
  }
  for (size_t t = 0; t < T; ++t) x[t] /= d[t];
  for (size_t t = T; t-- > 0;) {  // L^T x = y
    if (t + 1 < T) x[t] -= l1[t + 1] * x[t + 1];
    if (t + 2 < T) x[t] -= l2[t + 2] * x[t + 2];
  }
}

void CheckLambda(double lambda, const char* name) {
  if (!(lambda >= 0) || !std::isfinite(lambda)) {
    throw std::invalid_argument(std::string("fill smoothing: ") + name +
                                " expected a finite lambda >= 0, got " + std::to_string(lambda));
  }
}

}  // namespace

std::vector<float> SmoothFilledValues(const std::vector<float>& values,
                                      const std::vector<uint8_t>& mask, int coords,
                                      const FillSmoothing& s) {
  CheckLambda(s.bracketed, "bracketed");
  CheckLambda(s.one_sided, "one_sided");
  if (coords <= 0 || values.size() != mask.size() || values.size() % coords != 0) {
    throw std::invalid_argument("fill smoothing: expected values and mask of [frames, " +
                                std::to_string(coords) + "], got " + std::to_string(values.size()) +
                                " and " + std::to_string(mask.size()) + " values");
  }
  std::vector<float> out = values;
  const size_t N = static_cast<size_t>(coords), T = values.size() / N;
  if (!s.active() || T < 3) return out;
  std::vector<double> lambda(T);
  for (size_t v = 0; v < N; ++v) {
    // Each value's lambda: by whether an observed frame lies before and after it (0: held).
    std::vector<uint8_t> seen_before(T, 0);
    for (size_t t = 1; t < T; ++t) seen_before[t] = seen_before[t - 1] || !mask[(t - 1) * N + v];
    bool any_free = false, seen_after = false;
    for (size_t t = T; t-- > 0;) {
      if (!mask[t * N + v]) {
        lambda[t] = 0;
        seen_after = true;
        continue;
      }
      lambda[t] = seen_before[t] && seen_after   ? s.bracketed
                  : seen_before[t] || seen_after ? s.one_sided
                                                 : 0.0;
      any_free = any_free || lambda[t] > 0;
    }
    if (!any_free) continue;
    // Rows of the values held (observed, or lambda 0) are the identity; their terms move to the
    // right-hand side of the free rows.
    std::vector<std::array<double, 3>> band(T, {0.0, 0.0, 0.0});
    std::vector<double> b(T, 0.0);
    auto free = [&](size_t t) { return lambda[t] > 0; };
    auto x0 = [&](size_t t) { return static_cast<double>(values[t * N + v]); };
    for (size_t r = 1; r + 1 < T; ++r) {  // (x[r-1] - 2 x[r] + x[r+1])^2
      const size_t idx[3] = {r - 1, r, r + 1};
      const double c[3] = {1, -2, 1};
      for (int i = 0; i < 3; ++i) {
        if (!free(idx[i])) continue;
        for (int j = 0; j < 3; ++j) {
          if (free(idx[j])) {
            if (j >= i) band[idx[i]][j - i] += c[i] * c[j];
          } else {
            b[idx[i]] -= c[i] * c[j] * x0(idx[j]);
          }
        }
      }
    }
    for (size_t t = 0; t < T; ++t) {
      if (free(t)) {
        band[t][0] += 1.0 / lambda[t];
        b[t] += x0(t) / lambda[t];
      } else {
        band[t] = {1.0, 0.0, 0.0};
        b[t] = x0(t);
      }
    }
    SolvePentadiagonal(&band, &b);
    for (size_t t = 0; t < T; ++t)
      if (free(t)) out[t * N + v] = static_cast<float>(b[t]);
  }
  return out;
}

}  // namespace motionfork
