#include "imputation/window_gaussian.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "io/npy.h"

namespace motionfork {
namespace {

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Added to the observed block's diagonal before it is factorised, m^2: (0.03 mm)^2, far below what
// motion capture resolves, so that a near-singular block (two coordinates that move as one)
// cannot blow the estimate up.
constexpr double kJitter = 1e-9;

// Replaces the targets among frames [first, first + w) of values by their conditional mean given
// the observed values there, under the model's frames [model_first, model_first + w).
void Condition(const WindowGaussian& g, int model_first, size_t first, size_t w,
               const std::vector<uint8_t>& mask, const std::vector<uint8_t>& target,
               std::vector<float>* values) {
  const size_t N = static_cast<size_t>(g.coords), D = static_cast<size_t>(g.frames) * N;
  std::vector<size_t> obs, tgt;        // indices into the model's W * N
  std::vector<size_t> obs_at, tgt_at;  // the same values' indices into values
  for (size_t t = 0; t < w; ++t) {
    for (size_t v = 0; v < N; ++v) {
      const size_t at = (first + t) * N + v, m = (model_first + t) * N + v;
      if (!mask[at]) {
        obs.push_back(m);
        obs_at.push_back(at);
      } else if (target[at]) {
        tgt.push_back(m);
        tgt_at.push_back(at);
      }
    }
  }
  if (obs.empty() || tgt.empty()) return;
  Matrix soo(obs.size(), obs.size()), smo(tgt.size(), obs.size());
  Eigen::VectorXd d(obs.size());
  for (size_t i = 0; i < obs.size(); ++i) {
    for (size_t j = 0; j < obs.size(); ++j) soo(i, j) = g.cov[obs[i] * D + obs[j]];
    d(i) = (*values)[obs_at[i]] - g.mean[obs[i]];
  }
  for (size_t i = 0; i < tgt.size(); ++i)
    for (size_t j = 0; j < obs.size(); ++j) smo(i, j) = g.cov[tgt[i] * D + obs[j]];
  // A covariance of fewer independent windows than values, or rounded to float32 in the bundle,
  // can be singular to rounding: the jitter grows a hundredfold until the block factorises.
  Eigen::LLT<Matrix> llt;
  for (double jitter = kJitter; jitter <= 1e-3; jitter *= 100) {
    llt.compute(soo + jitter * Matrix::Identity(obs.size(), obs.size()));
    if (llt.info() == Eigen::Success) break;
  }
  if (llt.info() != Eigen::Success) return;  // keep the earlier fill
  const Eigen::VectorXd est = smo * llt.solve(d);
  for (size_t i = 0; i < tgt.size(); ++i) {
    if (std::isfinite(est(i))) (*values)[tgt_at[i]] = static_cast<float>(g.mean[tgt[i]] + est(i));
  }
}

}  // namespace

WindowGaussian FitWindowGaussian(const std::vector<std::vector<float>>& clips, int frames,
                                 int coords, int stride) {
  if (frames <= 0 || coords <= 0 || stride <= 0) {
    throw std::invalid_argument("window Gaussian: expected frames, coords and stride > 0, got " +
                                std::to_string(frames) + ", " + std::to_string(coords) + ", " +
                                std::to_string(stride));
  }
  const size_t N = static_cast<size_t>(coords), D = static_cast<size_t>(frames) * N;
  // Each clip's windows, in turn (every stride-th start).
  auto for_each_window = [&](const std::function<void(const float*)>& use) {
    for (size_t c = 0; c < clips.size(); ++c) {
      if (clips[c].size() % N != 0) {
        throw std::invalid_argument("window Gaussian: clip " + std::to_string(c) + " holds " +
                                    std::to_string(clips[c].size()) +
                                    " values, not a multiple of " + std::to_string(N) +
                                    " coordinates");
      }
      const size_t T = clips[c].size() / N;
      for (size_t s = 0; s + frames <= T; s += static_cast<size_t>(stride))
        use(clips[c].data() + s * N);
    }
  };
  // Two passes: the mean, then the outer products of the centred windows (no cancellation
  // between a large mean and a small spread), in blocks of windows.
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(D);
  long long count = 0;
  for_each_window([&](const float* w) {
    for (size_t i = 0; i < D; ++i) sum(i) += w[i];
    ++count;
  });
  if (count < 2) {
    throw std::invalid_argument("window Gaussian: expected at least 2 windows of " +
                                std::to_string(frames) + " frames in the clips, found " +
                                std::to_string(count));
  }
  const Eigen::VectorXd mean = sum / static_cast<double>(count);
  Eigen::MatrixXd outer = Eigen::MatrixXd::Zero(D, D);
  constexpr size_t kBlock = 2048;  // windows per rank update
  Eigen::MatrixXd block(kBlock, D);
  size_t rows = 0;
  auto flush = [&] {
    if (rows == 0) return;
    outer.selfadjointView<Eigen::Lower>().rankUpdate(block.topRows(rows).transpose());
    rows = 0;
  };
  for_each_window([&](const float* w) {
    for (size_t i = 0; i < D; ++i) block(rows, i) = w[i] - mean(i);
    if (++rows == kBlock) flush();
  });
  flush();
  WindowGaussian g;
  g.frames = frames;
  g.coords = coords;
  g.windows = count;
  g.mean.assign(mean.data(), mean.data() + D);
  g.cov.resize(D * D);
  for (size_t i = 0; i < D; ++i) {
    for (size_t j = 0; j <= i; ++j)
      g.cov[i * D + j] = g.cov[j * D + i] = outer(i, j) / static_cast<double>(count - 1);
  }
  return g;
}

const char* GaussianScopeName(GaussianScope scope) {
  return scope == GaussianScope::kOneSided ? "one_sided" : "short_motions";
}

GaussianScope ParseGaussianScope(const std::string& name) {
  if (name == "one_sided") return GaussianScope::kOneSided;
  if (name == "short_motions") return GaussianScope::kShortMotions;
  throw std::invalid_argument("window Gaussian scope: expected one_sided or short_motions, got '" +
                              name + "'");
}

std::vector<ObservedSpan> ObservedSpans(const std::vector<uint8_t>& mask, size_t coords) {
  const size_t T = coords > 0 ? mask.size() / coords : 0;
  std::vector<ObservedSpan> out(coords, ObservedSpan{T, T});
  for (size_t t = 0; t < T; ++t) {
    for (size_t v = 0; v < coords; ++v) {
      if (mask[t * coords + v]) continue;
      if (out[v].first == T) out[v].first = t;
      out[v].last = t;
    }
  }
  return out;
}

std::vector<float> FillFromWindowGaussian(const WindowGaussian& g, const std::vector<float>& values,
                                          const std::vector<uint8_t>& mask, GaussianScope scope) {
  const size_t N = static_cast<size_t>(g.coords);
  if (g.empty() || N == 0 || values.size() != mask.size() || values.size() % N != 0) {
    throw std::invalid_argument("window Gaussian fill: expected values and mask of [frames, " +
                                std::to_string(N) + "], got " + std::to_string(values.size()) +
                                " and " + std::to_string(mask.size()) + " values");
  }
  std::vector<float> out = values;
  const size_t T = values.size() / N;
  if (T == 0) return out;
  const size_t w = std::min(T, static_cast<size_t>(g.frames));
  const std::vector<ObservedSpan> seen = ObservedSpans(mask, N);
  const int model_tail = g.frames - static_cast<int>(w);
  if (scope == GaussianScope::kShortMotions && T <= static_cast<size_t>(g.frames)) {
    std::vector<uint8_t> target(values.size(), 0);
    for (size_t t = 0; t < T; ++t)
      for (size_t v = 0; v < N; ++v) target[t * N + v] = mask[t * N + v] && seen[v].first < T;
    Condition(g, model_tail, 0, w, mask, target, &out);
    return out;
  }
  // Targets: after the last observed frame within the last w frames (that frame among them too),
  // before the first within the first w.
  const size_t tail = T - w;
  std::vector<uint8_t> after(values.size(), 0), before(values.size(), 0);
  for (size_t v = 0; v < N; ++v) {
    if (seen[v].first == T) continue;
    if (seen[v].last >= tail)
      for (size_t t = seen[v].last + 1; t < T; ++t) after[t * N + v] = 1;
    if (seen[v].first < w)
      for (size_t t = 0; t < seen[v].first; ++t) before[t * N + v] = 1;
  }
  if (tail == 0) {  // one window holds both ends: one conditioning
    for (size_t i = 0; i < after.size(); ++i) after[i] = after[i] || before[i];
    Condition(g, model_tail, 0, w, mask, after, &out);
    return out;
  }
  Condition(g, model_tail, tail, w, mask, after, &out);
  Condition(g, 0, 0, w, mask, before, &out);
  return out;
}

std::string SerializeWindowGaussian(const WindowGaussian& g) {
  const int64_t D = static_cast<int64_t>(g.frames) * g.coords;
  NpyArray a;
  a.shape = {1 + D, D};
  a.data.reserve(static_cast<size_t>((1 + D) * D));
  for (double x : g.mean) a.data.push_back(static_cast<float>(x));
  for (double x : g.cov) a.data.push_back(static_cast<float>(x));
  return SerializeNpy(a);
}

WindowGaussian ParseWindowGaussian(const std::string& bytes, int frames, int coords,
                                   long long windows, const std::string& source_name) {
  const NpyArray a = ParseNpy(bytes, source_name);
  const int64_t D = static_cast<int64_t>(frames) * coords;
  if (frames <= 0 || coords <= 0 || a.shape != std::vector<int64_t>{1 + D, D}) {
    std::string found;
    for (int64_t s : a.shape) found += (found.empty() ? "" : ", ") + std::to_string(s);
    throw FormatError(source_name + ": expected a window Gaussian of shape [" +
                      std::to_string(1 + D) + ", " + std::to_string(D) + "] (" +
                      std::to_string(frames) + " frames x " + std::to_string(coords) +
                      " coordinates), found [" + found + "]");
  }
  WindowGaussian g;
  g.frames = frames;
  g.coords = coords;
  g.windows = windows;
  g.mean.assign(a.data.begin(), a.data.begin() + D);
  g.cov.assign(a.data.begin() + D, a.data.end());
  return g;
}

}  // namespace motionfork
