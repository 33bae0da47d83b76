#include "imputation/interpolation_fill.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "imputation/bone_lengths.h"

namespace motionfork {
namespace {

int CheckedFrames(const std::vector<float>& p, const std::vector<uint8_t>& missing, int joints,
                  const std::vector<float>& fallback, const char* what) {
  const size_t F = static_cast<size_t>(std::max(joints, 0)) * 3;
  if (joints < 1 || p.empty() || p.size() % F != 0 || missing.size() != p.size() ||
      (!fallback.empty() && fallback.size() != F)) {
    throw std::invalid_argument(std::string(what) + ": expected positions and a mask of frames x " +
                                std::to_string(joints) + " joints x 3 values (and a fallback of " +
                                std::to_string(F) + "), got " + std::to_string(p.size()) + ", " +
                                std::to_string(missing.size()) + " and " +
                                std::to_string(fallback.size()));
  }
  return static_cast<int>(p.size() / F);
}

[[noreturn]] void NeverObserved(const char* what, int joint) {
  throw std::invalid_argument(std::string(what) + ": joint " + std::to_string(joint) +
                              " is missing in every frame; pass a fallback pose (e.g. the "
                              "training mean) to fill it");
}

// Interpolation::kLocalPolynomial over the short gaps between the observed frames `at` of y.
void FillShortGapsByPolynomial(std::vector<double>* series, const std::vector<int>& at) {
  std::vector<double>& y = *series;
  const int n = static_cast<int>(at.size());
  std::vector<int> nodes;
  for (int i = 0; i + 1 < n; ++i) {
    const int a = at[i], b = at[i + 1];
    if (b - a - 1 < 1 || b - a - 1 > kLocalGapFrames) continue;
    nodes.clear();
    for (int k = i; k >= 0 && k > i - kLocalNodes && a - at[k] <= kLocalReach; --k)
      nodes.push_back(at[k]);
    for (int k = i + 1; k < n && k <= i + kLocalNodes && at[k] - b <= kLocalReach; ++k)
      nodes.push_back(at[k]);
    for (int t = a + 1; t < b; ++t) {  // Lagrange's form
      double value = 0;
      for (int p : nodes) {
        double w = 1;
        for (int q : nodes) {
          if (q != p) w *= double(t - q) / double(p - q);
        }
        value += w * y[p];
      }
      y[t] = value;
    }
  }
}

// Fills series[t] where !known[t] from the known frames (at least one), in place.
void FillSeries(std::vector<double>* series, const std::vector<char>& known, Interpolation kind) {
  std::vector<double>& y = *series;
  const int T = static_cast<int>(y.size());
  std::vector<int> at;  // observed frames
  for (int t = 0; t < T; ++t) {
    if (known[t]) at.push_back(t);
  }
  const int n = static_cast<int>(at.size());
  if (n == static_cast<int>(T)) return;
  for (int t = 0; t < at.front(); ++t) y[t] = y[at.front()];
  for (int t = at.back() + 1; t < T; ++t) y[t] = y[at.back()];
  if (kind == Interpolation::kLinear || n < 3) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = at[i], b = at[i + 1];
      for (int t = a + 1; t < b; ++t) y[t] = y[a] + (y[b] - y[a]) * (t - a) / double(b - a);
    }
    return;
  }
  // Natural cubic spline: second derivatives m (m = 0 at both ends) from the tridiagonal system.
  std::vector<double> h(n - 1), m(n, 0.0), c(n, 0.0), d(n, 0.0);
  for (int i = 0; i + 1 < n; ++i) h[i] = at[i + 1] - at[i];
  for (int i = 1; i + 1 < n; ++i) {  // Thomas algorithm, forward sweep
    const double lower = h[i - 1], diag = 2 * (h[i - 1] + h[i]), upper = h[i];
    const double rhs =
        6 * ((y[at[i + 1]] - y[at[i]]) / h[i] - (y[at[i]] - y[at[i - 1]]) / h[i - 1]);
    const double denom = diag - lower * c[i - 1];
    c[i] = upper / denom;
    d[i] = (rhs - lower * d[i - 1]) / denom;
  }
  for (int i = n - 2; i >= 1; --i) m[i] = d[i] - c[i] * m[i + 1];
  for (int i = 0; i + 1 < n; ++i) {
    const int a = at[i], b = at[i + 1];
    for (int t = a + 1; t < b; ++t) {
      const double u = (b - t) / h[i], v = (t - a) / h[i];
      y[t] = u * y[a] + v * y[b] +
             ((u * u * u - u) * m[i] + (v * v * v - v) * m[i + 1]) * h[i] * h[i] / 6.0;
    }
  }
  if (kind == Interpolation::kLocalPolynomial) FillShortGapsByPolynomial(&y, at);
}

}  // namespace

std::vector<float> InterpolateMissing(const std::vector<float>& positions,
                                      const std::vector<uint8_t>& missing, int joints,
                                      Interpolation kind, const std::vector<float>& fallback) {
  const int T = CheckedFrames(positions, missing, joints, fallback, "InterpolateMissing");
  const size_t F = static_cast<size_t>(joints) * 3;
  std::vector<float> out = positions;
  std::vector<double> series(T);
  std::vector<char> known(T);
  // The root first (world coordinates), then the others relative to the filled root.
  for (int j = 0; j < joints; ++j) {
    for (int a = 0; a < 3; ++a) {
      const size_t v = static_cast<size_t>(j) * 3 + a;
      int observed = 0;
      for (int t = 0; t < T; ++t) {
        const size_t i = t * F + v;
        known[t] = !missing[i];
        observed += known[t];
        series[t] = known[t] ? positions[i] - (j > 0 ? out[t * F + a] : 0.0f) : 0.0;
      }
      if (observed == T) continue;
      if (observed == 0) {
        if (fallback.empty()) NeverObserved("InterpolateMissing", j);
        for (int t = 0; t < T; ++t) out[t * F + v] = (j > 0 ? out[t * F + a] : 0.0f) + fallback[v];
        continue;
      }
      FillSeries(&series, known, kind);
      for (int t = 0; t < T; ++t) {
        if (!known[t])
          out[t * F + v] = static_cast<float>(series[t] + (j > 0 ? out[t * F + a] : 0.0));
      }
    }
  }
  return out;
}

std::vector<float> RigidLimbFill(const Skeleton& skeleton, const std::vector<float>& positions,
                                 const std::vector<uint8_t>& missing,
                                 const std::vector<float>& fallback) {
  const int J = skeleton.num_joints();
  const int T = CheckedFrames(positions, missing, J, fallback, "RigidLimbFill");
  const size_t F = static_cast<size_t>(J) * 3;
  // The root by linear interpolation; every other joint is placed below.
  std::vector<uint8_t> root_only(missing.size(), 0);
  for (int t = 0; t < T; ++t)
    for (int a = 0; a < 3; ++a) root_only[t * F + a] = missing[t * F + a];
  std::vector<float> out =
      InterpolateMissing(positions, root_only, J, Interpolation::kLinear, fallback);
  auto whole = [&](int t, int j) {  // all three coordinates observed
    const size_t i = t * F + static_cast<size_t>(j) * 3;
    return !missing[i] && !missing[i + 1] && !missing[i + 2];
  };
  const std::vector<ObservedBone> bones = ObservedBones(skeleton, positions, missing);
  for (int j = 1; j < J; ++j) {
    const int parent = skeleton.parent(j);
    std::vector<int> at;       // frames where the bone is observed
    std::vector<double> dirs;  // [at, 3] unit vectors
    bool gaps = false;
    for (int t = 0; t < T; ++t) {
      gaps = gaps || !whole(t, j);
      if (!whole(t, j) || !whole(t, parent)) continue;
      double b[3], len = 0;
      for (int a = 0; a < 3; ++a) {
        b[a] = positions[t * F + j * 3 + a] - positions[t * F + parent * 3 + a];
        len += b[a] * b[a];
      }
      len = std::sqrt(len);
      if (len <= 0) continue;
      at.push_back(t);
      for (double x : b) dirs.push_back(x / len);
    }
    if (!gaps) continue;
    double length = 0, fixed_dir[3] = {0, 0, 0};
    if (at.empty()) {
      if (fallback.empty()) NeverObserved("RigidLimbFill", j);
      for (int a = 0; a < 3; ++a) {
        fixed_dir[a] = fallback[j * 3 + a] - fallback[parent * 3 + a];
        length += fixed_dir[a] * fixed_dir[a];
      }
      length = std::sqrt(length);
      for (double& x : fixed_dir) x = length > 0 ? x / length : 0.0;
    } else {
      length = bones[j].length;  // the median over the frames in `at`
    }
    size_t next = 0;  // first observed bone frame >= t
    for (int t = 0; t < T; ++t) {
      while (next < at.size() && at[next] < t) ++next;
      if (whole(t, j)) continue;
      double d[3];
      if (at.empty()) {
        std::copy(fixed_dir, fixed_dir + 3, d);
      } else if (next == 0 || next == at.size()) {  // beyond the observed frames: the nearest
        const size_t k = next == 0 ? 0 : at.size() - 1;
        std::copy(dirs.begin() + 3 * k, dirs.begin() + 3 * k + 3, d);
      } else {
        const int a0 = at[next - 1], a1 = at[next];
        const double w = double(t - a0) / (a1 - a0);
        double norm = 0;
        for (int a = 0; a < 3; ++a) {
          d[a] = (1 - w) * dirs[3 * (next - 1) + a] + w * dirs[3 * next + a];
          norm += d[a] * d[a];
        }
        norm = std::sqrt(norm);
        for (double& x : d) x = norm > 1e-9 ? x / norm : 0.0;
      }
      for (int a = 0; a < 3; ++a) {
        const size_t i = t * F + static_cast<size_t>(j) * 3 + a;
        if (missing[i]) out[i] = static_cast<float>(out[t * F + parent * 3 + a] + length * d[a]);
      }
    }
  }
  return out;
}

}  // namespace motionfork
