#include "imputation/blend_fit.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace motionfork {

void BlendSums::Add(double e, double c, double l) {
  v[kEE] += e * e;
  v[kCE] += c * e;
  v[kCC] += c * c;
  v[kLE] += l * e;
  v[kLL] += l * l;
  v[kCL] += c * l;
  ++values;
}

BlendSums& BlendSums::operator+=(const BlendSums& o) {
  for (int p = 0; p < kProducts; ++p) v[p] += o.v[p];
  values += o.values;
  return *this;
}

BlendSums BlendSums::Scaled(double s) const {
  BlendSums out = *this;
  for (double& x : out.v) x *= s;
  return out;
}

double BlendSquares(const BlendSums& s, double a, double b) {
  const auto& v = s.v;
  using P = BlendSums;
  return v[P::kEE] - 2 * a * v[P::kCE] - 2 * b * v[P::kLE] + a * a * v[P::kCC] + b * b * v[P::kLL] +
         2 * a * b * v[P::kCL];
}

double BlendSquares(const BucketSums& s, const std::vector<double>& a,
                    const std::vector<double>& b) {
  double total = 0;
  for (size_t k = 0; k < s.size(); ++k) total += BlendSquares(s[k], a[k], b[k]);
  return total;
}

// The unconstrained minimum when inside [0, 1]^2, else the best of each edge's minimum and the
// corners.
std::pair<double, double> BestBlendWeights(const BlendSums& s) {
  const auto& v = s.v;
  using P = BlendSums;
  std::vector<std::pair<double, double>> candidates = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  const double det = v[P::kCC] * v[P::kLL] - v[P::kCL] * v[P::kCL];
  if (det > 1e-12 * std::max(1e-300, v[P::kCC] * v[P::kLL])) {
    candidates.push_back({(v[P::kCE] * v[P::kLL] - v[P::kLE] * v[P::kCL]) / det,
                          (v[P::kLE] * v[P::kCC] - v[P::kCE] * v[P::kCL]) / det});
  }
  for (double fixed : {0.0, 1.0}) {  // one weight on an edge, the other at its best
    if (v[P::kCC] > 0) candidates.push_back({(v[P::kCE] - fixed * v[P::kCL]) / v[P::kCC], fixed});
    if (v[P::kLL] > 0) candidates.push_back({fixed, (v[P::kLE] - fixed * v[P::kCL]) / v[P::kLL]});
  }
  std::pair<double, double> best{0, 0};
  for (auto [a, b] : candidates) {
    if (!(a >= 0 && a <= 1 && b >= 0 && b <= 1)) continue;
    if (BlendSquares(s, a, b) < BlendSquares(s, best.first, best.second)) best = {a, b};
  }
  return best;
}

std::pair<double, double> BestBlendWeights(const BlendSums& s, double a0, double b0,
                                           double prior_values) {
  using P = BlendSums;
  const auto& v = s.v;
  if (s.values <= 0 || !(v[P::kCC] > 0 || v[P::kLL] > 0)) return {a0, b0};
  // prior_values more values with the same corrections, whose errors a0 c + b0 l fits exactly.
  const double w = prior_values / static_cast<double>(s.values);
  BlendSums pulled = s;
  pulled.v[P::kEE] += w * (a0 * a0 * v[P::kCC] + 2 * a0 * b0 * v[P::kCL] + b0 * b0 * v[P::kLL]);
  pulled.v[P::kCE] += w * (a0 * v[P::kCC] + b0 * v[P::kCL]);
  pulled.v[P::kLE] += w * (a0 * v[P::kCL] + b0 * v[P::kLL]);
  pulled.v[P::kCC] += w * v[P::kCC];
  pulled.v[P::kLL] += w * v[P::kLL];
  pulled.v[P::kCL] += w * v[P::kCL];
  return BestBlendWeights(pulled);
}

void AddBlendSums(const RefinerFills& f, const std::vector<float>& refined,
                  const std::vector<float>& truth, const std::vector<uint8_t>& which,
                  BucketSums* sums) {
  const size_t n = f.mask.size();
  if (refined.size() != n || truth.size() != n || which.size() != n || f.spline.size() != n ||
      f.local.size() != n) {
    throw std::invalid_argument("AddBlendSums: expected " + std::to_string(n) +
                                " values in each input");
  }
  sums->resize(kRefinerGapBuckets);
  const std::vector<int> buckets = RefinerGapBuckets(f);
  for (size_t i = 0; i < n; ++i) {
    if (!which[i] || buckets[i] < 0) continue;
    (*sums)[buckets[i]].Add(double(truth[i]) - f.spline[i], double(refined[i]) - f.spline[i],
                            double(f.local[i]) - f.spline[i]);
  }
}

}  // namespace motionfork
