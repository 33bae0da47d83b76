#include "eval/evaluate.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include "core/parallel_for.h"

namespace motionfork {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Running sums for one group of windows.
struct Sums {
  int windows = 0;
  WindowMetrics metrics;
  double set_size = 0;
  double apd_varied = 0, apd_fixed = 0;
  std::vector<double> predicted, truth;  // [scorers] per-window means
  RootFigures root;

  explicit Sums(size_t scorers) : predicted(scorers, 0.0), truth(scorers, 0.0) {}

  void Add(const WindowMetrics& m, int set_size, double varied, double fixed,
           const std::vector<double>& pred, const std::vector<double>& gt, const RootFigures& r) {
    ++windows;
    metrics += m;
    root += r;
    this->set_size += set_size;
    apd_varied += varied;
    apd_fixed += fixed;
    for (size_t s = 0; s < predicted.size(); ++s) {
      predicted[s] += pred[s];
      truth[s] += gt[s];
    }
  }

  // Every window has the same number of frames, so the mean of per-window frame means is the
  // mean over frames.
  Figures Mean() const {
    Figures f;
    f.windows = windows;
    if (windows == 0) return f;
    const double n = windows;
    static_cast<WindowMetrics&>(f) = metrics / n;
    f.mean_set_size = set_size / n;
    f.apd_varied = apd_varied / n;
    f.apd_fixed = apd_fixed / n;
    f.root = root / n;
    for (size_t s = 0; s < predicted.size(); ++s) {
      f.predicted_scores.push_back(predicted[s] / n);
      f.truth_scores.push_back(truth[s] / n);
    }
    return f;
  }
};

// Mean of a scorer over n frames [n, J, 3].
double MeanScore(const FrameScorer& scorer, const float* positions, int n,
                 std::vector<double>* scratch, int window) {
  scratch->assign(n, 0.0);
  scorer.score(positions, n, scratch->data());
  double sum = 0;
  for (double s : *scratch) {
    if (!std::isfinite(s)) {
      throw std::invalid_argument("scorer '" + scorer.name +
                                  "' returned a non-finite score in window " +
                                  std::to_string(window));
    }
    sum += s;
  }
  return sum / n;
}

// The root figures of one window: futures [K, T, J, 3] world; truth_positions [T, J, 3] scratch.
RootFigures MeasureRoot(const RootOptions& o, const TestSet& ts, int i, const float* futures, int K,
                        std::vector<float>* truth_positions) {
  const int T = ts.t_pred, J = ts.num_joints();
  RootFigures r;
  const Displacement d = RootMinDisplacement(futures, K, T, J, ts.root_future(i));
  r.ade = d.ade;
  r.fde = d.fde;
  r.final_spread = FinalRootSpread(futures, K, T, J, o.up);
  if (o.feet.empty()) return r;
  const double ground = GroundHeight(ts.history(i), ts.t_his, J, o.feet, o.up);
  for (int k = 0; k < K; ++k) {
    r.skating += FootSkating(futures + static_cast<size_t>(k) * T * J * 3, T, J, o.feet, o.up,
                             ground, o.contact_height);
  }
  r.skating /= K;
  // The ground truth in world coordinates: its root-relative pose vectors on its root.
  const float* gt = ts.future(i);
  const float* root = ts.root_future(i);
  truth_positions->resize(static_cast<size_t>(T) * J * 3);
  for (int t = 0; t < T; ++t) {
    float* q = truth_positions->data() + static_cast<size_t>(t) * J * 3;
    for (int a = 0; a < 3; ++a) q[a] = root[3 * t + a];
    for (int e = 3; e < J * 3; ++e)
      q[e] = gt[static_cast<size_t>(t) * (J - 1) * 3 + e - 3] + q[e % 3];
  }
  r.truth_skating =
      FootSkating(truth_positions->data(), T, J, o.feet, o.up, ground, o.contact_height);
  return r;
}

}  // namespace

uint64_t WindowSeed(uint64_t seed, int window) { return ItemSeed(seed, window); }

EvalResult Evaluate(Predictor& predictor, const TestSet& ts, const EvalOptions& options) {
  const int N = ts.num_windows();
  const int K = options.num_samples;
  const int T = ts.t_pred;
  const int D = ts.pose_dims;
  const int J = ts.num_joints();
  if (!predictor.skeleton().SameStructure(*ts.skeleton)) {
    throw std::invalid_argument(
        predictor.name() + " works on skeleton '" + predictor.skeleton().name() + "' (" +
        std::to_string(predictor.skeleton().num_joints()) + " joints); the test windows are on '" +
        ts.skeleton->name() + "' (" + std::to_string(J) +
        " joints): expected the protocol's skeleton");
  }
  if (predictor.t_his() != ts.t_his || predictor.t_pred() != T) {
    throw std::invalid_argument(predictor.name() + " predicts " +
                                std::to_string(predictor.t_pred()) + " frames from " +
                                std::to_string(predictor.t_his()) + "; the protocol expects " +
                                std::to_string(T) + " from " + std::to_string(ts.t_his));
  }
  if (ts.multimodal.num_windows() != N) {
    throw std::invalid_argument("Evaluate: expected multimodal sets for " + std::to_string(N) +
                                " windows, got " + std::to_string(ts.multimodal.num_windows()) +
                                " (call AttachMultimodalSets first)");
  }
  if (K < 2) {
    throw std::invalid_argument(
        "Evaluate: expected K >= 2 samples (APD is a mean over pairs of "
        "samples), got " +
        std::to_string(K));
  }
  std::vector<int> fixed_dims, varied_dims;
  EvalResult result;
  if (options.fixed_part >= 0) {
    const Partition& partition = ts.skeleton->GetPartition();
    if (options.fixed_part >= static_cast<int>(partition.parts.size())) {
      throw std::invalid_argument("Evaluate: expected fixed_part in [0, " +
                                  std::to_string(partition.parts.size()) + "), got " +
                                  std::to_string(options.fixed_part));
    }
    const BodyPart& part = partition.parts[options.fixed_part];
    result.fixed_part = part.name;
    std::vector<char> in_part(J, 0);
    for (int j : part.joints) in_part[j] = 1;
    for (int j = 1; j < J; ++j) {
      for (int a = 0; a < 3; ++a)
        (in_part[j] ? fixed_dims : varied_dims).push_back(3 * (j - 1) + a);
    }
  }
  if (options.root.enabled && ts.root_futures.size() != static_cast<size_t>(N) * T * 3) {
    throw std::invalid_argument("Evaluate: root figures need the test windows' root futures (" +
                                std::to_string(N) + " x " + std::to_string(T) + " x 3), got " +
                                std::to_string(ts.root_futures.size()) + " numbers");
  }
  for (const FrameScorer& s : options.scorers) {
    if (!s.score) throw std::invalid_argument("Evaluate: scorer '" + s.name + "' has no function");
  }
  const size_t scorers = options.scorers.size();
  result.num_samples = K;
  result.seed = options.seed;
  result.per_window.assign(N, WindowMetrics{});
  result.evaluated.assign(N, 0);

  // Each window is measured on its own (its seed is WindowSeed(seed, i)), by `threads` threads
  // taking windows in turn; the sums are then taken in window order, so that the figures do not
  // depend on the number of threads.
  struct Outcome {
    bool skipped = false;
    WindowMetrics m;
    double varied = 0, fixed = 0;
    std::vector<double> pred_scores, truth_scores;
    RootFigures root;
  };
  std::vector<Outcome> outcomes(N);
  std::atomic<int> done{0};
  std::mutex progress_lock;
  struct Scratch {
    std::vector<float> history, futures, samples, relative, truth_positions, truth_world;
    std::vector<const float*> truths;
    std::vector<Displacement> displacements;
    std::vector<double> scratch;
    DisplacementWorkspace workspace;
    double time[3] = {0, 0, 0};  // predicting, metrics, scoring
  };
  const int threads = std::max(1, std::min(options.threads, N));
  std::vector<Scratch> scratches(threads);
  for (Scratch& s : scratches) {
    s.samples.resize(static_cast<size_t>(K) * T * D);       // [K, T, D]
    s.relative.resize(static_cast<size_t>(K) * T * J * 3);  // [K * T, J, 3] root at 0
    s.truth_positions.resize(static_cast<size_t>(T) * J * 3);
  }
  auto report = [&] {
    const int d = ++done;
    if (!options.progress) return;
    std::lock_guard<std::mutex> lock(progress_lock);
    options.progress(d, N);
  };
  auto measure = [&](int i, int worker) {
    Scratch& w = scratches[worker];
    Outcome& o = outcomes[i];
    const int set_size = ts.multimodal.set_size(i);
    if (!options.keep_singleton_sets && set_size == 1) {
      o.skipped = true;
      report();
      return;
    }
    auto start = Clock::now();
    w.history.assign(ts.history(i), ts.history(i) + static_cast<size_t>(ts.t_his) * J * 3);
    PredictRequest request;
    request.num_samples = K;
    request.seed = WindowSeed(options.seed, i);
    request.fixed_part = options.fixed_part;
    predictor.Predict(w.history, request, &w.futures);
    w.time[0] += Since(start);

    start = Clock::now();
    for (size_t f = 0; f < static_cast<size_t>(K) * T; ++f) {
      const float* p = w.futures.data() + f * J * 3;
      float* r = w.relative.data() + f * J * 3;
      float* s = w.samples.data() + f * D;
      for (int e = 0; e < J * 3; ++e) {
        if (!std::isfinite(p[e])) {
          throw std::invalid_argument(
              predictor.name() + " returned a non-finite position in window " + std::to_string(i) +
              " (clip '" + ts.clip_names[ts.windows[i].clip] + "', start frame " +
              std::to_string(ts.windows[i].start) + ")");
        }
        r[e] = p[e] - p[e % 3];
      }
      std::copy(r + 3, r + J * 3, s);
    }
    WindowMetrics& m = o.m;
    m.apd = Apd(w.samples.data(), K, T, D);
    w.truths.clear();
    int self = -1;
    for (int k = 0; k < set_size; ++k) {
      const int member = ts.multimodal.set(i)[k];
      if (member == i) self = k;
      w.truths.push_back(ts.future(member));
    }
    if (self < 0) {
      throw std::invalid_argument(
          "Evaluate: window " + std::to_string(i) +
          " is missing from its own multimodal set (sets built for other windows?)");
    }
    w.workspace.Run(w.samples.data(), K, T, D, w.truths, &w.displacements);
    m.ade = w.displacements[self].ade;
    m.fde = w.displacements[self].fde;
    for (const Displacement& d : w.displacements) {
      m.mmade += d.ade;
      m.mmfde += d.fde;
    }
    m.mmade /= set_size;
    m.mmfde /= set_size;
    if (options.root.enabled) {
      o.root = MeasureRoot(options.root, ts, i, w.futures.data(), K, &w.truth_world);
    }
    if (options.fixed_part >= 0) {
      if (!varied_dims.empty()) o.varied = ApdOfDims(w.samples.data(), K, T, D, varied_dims);
      if (!fixed_dims.empty()) o.fixed = ApdOfDims(w.samples.data(), K, T, D, fixed_dims);
    }
    w.time[1] += Since(start);

    o.pred_scores.assign(scorers, 0.0);
    o.truth_scores.assign(scorers, 0.0);
    if (scorers > 0) {
      start = Clock::now();
      const float* gt = ts.future(i);
      for (int t = 0; t < T; ++t) {
        float* q = w.truth_positions.data() + static_cast<size_t>(t) * J * 3;
        q[0] = q[1] = q[2] = 0;
        std::copy(gt + static_cast<size_t>(t) * D, gt + static_cast<size_t>(t + 1) * D, q + 3);
      }
      for (size_t s = 0; s < scorers; ++s) {
        o.pred_scores[s] = MeanScore(options.scorers[s], w.relative.data(), K * T, &w.scratch, i);
        o.truth_scores[s] =
            MeanScore(options.scorers[s], w.truth_positions.data(), T, &w.scratch, i);
      }
      w.time[2] += Since(start);
    }
    report();
  };
  ParallelFor(N, threads, measure);
  for (const Scratch& w : scratches) {
    result.seconds_predicting += w.time[0];
    result.seconds_metrics += w.time[1];
    result.seconds_scoring += w.time[2];
  }
  Sums all(scorers);
  std::vector<Sums> per_action(ts.actions.size(), Sums(scorers));
  for (int i = 0; i < N; ++i) {
    const Outcome& o = outcomes[i];
    if (o.skipped) {
      ++result.windows_skipped;
      continue;
    }
    const int set_size = ts.multimodal.set_size(i);
    result.per_window[i] = o.m;
    result.evaluated[i] = 1;
    all.Add(o.m, set_size, o.varied, o.fixed, o.pred_scores, o.truth_scores, o.root);
    per_action[ts.action[i]].Add(o.m, set_size, o.varied, o.fixed, o.pred_scores, o.truth_scores,
                                 o.root);
  }
  if (all.windows == 0) {
    throw std::invalid_argument("Evaluate: every one of the " + std::to_string(N) +
                                " windows has a singleton multimodal set and was skipped "
                                "(keep_singleton_sets is false)");
  }
  result.overall = all.Mean();
  for (const Sums& s : per_action) result.per_action.push_back(s.Mean());
  return result;
}

}  // namespace motionfork
