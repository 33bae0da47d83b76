#include "imputation/training/hgvae_evaluation.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "core/resample.h"
#include "imputation/gap_imputation.h"
#include "imputation/occlusion.h"

namespace motionfork {
namespace {

double Mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

HgvaeLikelihood Likelihood(const HgvaeModel& model, const std::vector<float>& windows,
                           uint64_t seed) {
  const HgvaeWindowFigures f = model.Evaluate(windows, seed);
  HgvaeLikelihood l{Mean(f.elbo), Mean(f.recon_mse), Mean(f.recon_mse_sampled), {}};
  for (const auto& level : f.kl_levels) {
    l.kl_levels.push_back(Mean(level));
    l.kl_total += Mean(level);
  }
  l.posterior_score_mean = Mean(f.score);
  l.joint_score_mean = Mean(f.joint_score);
  return l;
}

// AUROC of both scores, clean vs degraded; flagged by the bundle's score.
void OodTests(const HgvaeModel& model, const std::vector<float>& windows, uint64_t seed,
              HgvaeEvaluation* out) {
  const int count = out->windows;
  const std::vector<double> clean = model.Score(windows);
  const std::vector<double> clean_post = model.Score(windows, ImputeObjective::kPosterior);
  const std::vector<double> clean_joint = model.Score(windows, ImputeObjective::kJoint);
  std::vector<std::pair<std::string, std::vector<float>>> degraded;
  for (double s : {0.005, 0.05, 0.5}) {
    char name[64];
    std::snprintf(name, sizeof(name), "%.3g%% values -> mean", 100 * s);
    degraded.emplace_back(name, ReplaceWithMean(model, windows, s, seed + 7));
  }
  degraded.emplace_back("bones x1.5", ScaleBones(model.skeleton(), windows, 1.5f));
  degraded.emplace_back("bones x0.7", ScaleBones(model.skeleton(), windows, 0.7f));
  degraded.emplace_back("shuffled frames", ShuffleFrames(windows, model.coords(), seed + 11));
  int clean_flagged = 0;
  for (double s : clean) clean_flagged += model.OutOfDistribution(s);
  out->clean_flagged = double(clean_flagged) / count;
  for (const auto& [name, w] : degraded) {
    int flagged = 0;
    for (double x : model.Score(w)) flagged += model.OutOfDistribution(x);
    out->ood.push_back({name, Auroc(clean_joint, model.Score(w, ImputeObjective::kJoint)),
                        Auroc(clean_post, model.Score(w, ImputeObjective::kPosterior)),
                        double(flagged) / count});
  }
}

// H histories [H, T, N] (root-relative, root dropped) with mask [H, T, N] filled by a whole-motion
// method (gap_imputation.h), each history a motion of its own with the root at the origin: what
// `predict --impute` does with a history.
std::vector<float> FillHistories(FillMethod method, const HgvaeModel& model,
                                 const std::vector<float>& hist, const std::vector<uint8_t>& mask,
                                 int H, const ImputeOptions& options) {
  const int T = model.window(), N = static_cast<int>(model.coords()), J = N / 3 + 1;
  const auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  std::vector<float> out(hist.size());
  for (int h = 0; h < H; ++h) {
    std::vector<float> positions(static_cast<size_t>(T) * J * 3, 0.0f);
    std::vector<uint8_t> missing(positions.size(), 0);
    for (int t = 0; t < T; ++t) {
      for (int v = 0; v < N; ++v) {
        const size_t from = (static_cast<size_t>(h) * T + t) * N + v,
                     to = static_cast<size_t>(t) * J * 3 + 3 + v;
        positions[to] = hist[from];
        missing[to] = mask[from];
      }
    }
    const Motion motion(skeleton, model.manifest().fps, positions);
    const std::vector<float> filled = FillMotion(method, model, motion, missing, options);
    for (int t = 0; t < T; ++t) {
      const size_t f = static_cast<size_t>(t) * J * 3;
      for (int v = 0; v < N; ++v)
        out[(static_cast<size_t>(h) * T + t) * N + v] = filled[f + 3 + v] - filled[f + v % 3];
    }
  }
  return out;
}

// Throws std::invalid_argument naming a forecasting row the options ask for that is not one of the
// standard occlusions, or rows asked for without a forecaster (before any work is done).
void CheckForecastOcclusions(const HgvaeModel& model, const HgvaeEvalOptions& o) {
  if (!o.forecast_occlusions.empty() && !o.forecaster.forecast)
    throw std::invalid_argument("forecasting rows were named, but no forecaster was given");
  const std::vector<Occlusion> settings = StandardOcclusions(model.skeleton());
  for (const std::string& name : o.forecast_occlusions) {
    if (std::none_of(settings.begin(), settings.end(),
                     [&name](const Occlusion& oc) { return oc.name == name; })) {
      std::string known;
      for (const Occlusion& oc : settings) known += (known.empty() ? "'" : ", '") + oc.name + "'";
      throw std::invalid_argument("no forecasting occlusion '" + name + "'; expected one of " +
                                  known);
    }
  }
}

// Forecasting from clean, mean-imputed and HG-VAE-imputed histories of protocol test windows
// (the HG-VAE's window imputation with the options' steps, 10 where they are 0), and from the
// same histories filled over the history alone by linear and spline interpolation, rigid limbs and
// the bundle's refiner (when it has one).
ForecastingFigures Forecasting(const HgvaeModel& model, const Dataset& ds,
                               const HgvaeEvalOptions& o) {
  const int T = model.window();
  if (o.forecaster.t_his != T) {
    throw std::invalid_argument("the forecaster's history is " +
                                std::to_string(o.forecaster.t_his) +
                                " frames, the HG-VAE's window " + std::to_string(T));
  }
  std::vector<const Clip*> test_clips;
  for (int c : ds.ClipIndices(Split::kTest)) test_clips.push_back(&ds.clips[c]);
  const TestSet ts = BuildTestSet(test_clips, ds.protocol);
  const HistoryForecastProbe probe(ts, o.forecast_windows, o.k, o.forecaster);
  const int H = probe.count(), J = ts.num_joints();
  const std::vector<float> hist = probe.Histories();
  ForecastingFigures f{o.forecaster.name, o.k, H, probe.Score(hist), {}};
  const std::vector<Occlusion> settings = StandardOcclusions(model.skeleton());
  for (size_t s = 0; s < settings.size(); ++s) {
    const Occlusion& oc = settings[s];
    if (!o.forecast_occlusions.empty() &&
        std::find(o.forecast_occlusions.begin(), o.forecast_occlusions.end(), oc.name) ==
            o.forecast_occlusions.end())
      continue;
    const std::vector<uint8_t> mask =
        oc.share > 0 ? RandomOcclusion(H, T * model.coords(), oc.share, o.seed + 99 + s)
                     : JointOcclusion(H, T, J, oc.joints);
    ImputeOptions steps = o.impute;
    if (steps.steps == 0) steps.steps = ImputeOptions{}.steps;
    RepairedForecast r{oc.name,
                       probe.Score(model.MeanImpute(hist, mask)),
                       probe.Score(model.Impute(hist, mask, steps).windows),
                       {}};
    for (FillMethod m : {FillMethod::kLinear, FillMethod::kCubicSpline, FillMethod::kRigidLimb,
                         FillMethod::kRefiner}) {
      if (m == FillMethod::kRefiner && !model.has_refiner()) continue;
      r.others.emplace_back(FillMethodName(m),
                            probe.Score(FillHistories(m, model, hist, mask, H, o.impute)));
    }
    f.settings.push_back(std::move(r));
    ReportProgress(o.progress, "forecasting", double(s + 1) / settings.size());
  }
  return f;
}

// The dataset with its test clips played `factor` times slower (the others as they are).
Dataset SlowedTestClips(const Dataset& ds, double factor) {
  Dataset out = ds;
  for (int c : ds.ClipIndices(Split::kTest)) {
    Motion& m = out.clips[c].motion;
    m = Motion(m.skeleton_ptr(), m.fps(), SlowDown(m.positions(), m.num_joints(), factor));
  }
  return out;
}

}  // namespace

std::vector<float> HgvaeTestWindows(const Dataset& ds, int window, int limit) {
  std::vector<float> all;
  int count = 0;
  for (int c : ds.ClipIndices(Split::kTest)) {
    const std::vector<float> p = PoseVectorsWithoutRoot(ds.clips[c].motion);
    const int N = 3 * (ds.clips[c].motion.num_joints() - 1), T = ds.clips[c].motion.num_frames();
    for (int s = 0; s + window <= T; s += window, ++count) {
      all.insert(all.end(), p.begin() + static_cast<size_t>(s) * N,
                 p.begin() + static_cast<size_t>(s + window) * N);
    }
  }
  if (count == 0) {
    throw std::invalid_argument("no test clip is " + std::to_string(window) + " frames long");
  }
  if (count <= limit) return all;
  const size_t per = all.size() / count;
  std::vector<float> out;
  for (int i = 0; i < limit; ++i) {
    const size_t w = static_cast<size_t>(i) * count / limit;
    out.insert(out.end(), all.begin() + w * per, all.begin() + (w + 1) * per);
  }
  return out;
}

HgvaeEvaluation EvaluateHgvae(const HgvaeModel& model, const Dataset& given,
                              const HgvaeEvalOptions& o) {
  CheckForecastOcclusions(model, o);
  if (!(o.slow > 0)) throw std::invalid_argument("slow must be > 0, not " + std::to_string(o.slow));
  const Dataset slowed = o.slow == 1 ? Dataset{} : SlowedTestClips(given, o.slow);
  const Dataset& dataset = o.slow == 1 ? given : slowed;
  const std::vector<float> windows = HgvaeTestWindows(dataset, model.window(), o.windows);
  const HgvaeManifest& m = model.manifest();
  HgvaeEvaluation e;
  e.window_frames = model.window();
  e.slow = o.slow;
  e.windows =
      static_cast<int>(windows.size() / (static_cast<size_t>(e.window_frames) * model.coords()));
  e.stochastic_levels = m.model.stochastic_levels == 0 ? static_cast<int>(m.model.levels.size())
                                                       : m.model.stochastic_levels;
  e.likelihood = Likelihood(model, windows, o.seed);
  e.likelihood_only = o.likelihood_only;
  if (o.likelihood_only) return e;
  e.imputation = ImputationExperiment(
      model, windows, StandardOcclusions(model.skeleton()), o.impute, o.seed,
      [&o](int d, int t) { ReportProgress(o.progress, "imputation", double(d) / t); });
  std::vector<Motion> clips;
  const std::vector<int> test = dataset.ClipIndices(Split::kTest);
  const int used = std::min<int>(o.gap_clips, static_cast<int>(test.size()));
  for (int i = 0; i < used; ++i)
    clips.push_back(dataset.clips[test[static_cast<size_t>(i) * test.size() / used]].motion);
  e.gap_clips = used;
  if (used > 0)
    e.gaps = GapExperiment(
        model, clips, StandardGapSettings(model.skeleton(), model.manifest().fps), o.impute,
        o.seed + 31, [&o](int d, int t) { ReportProgress(o.progress, "gaps", double(d) / t); });
  OodTests(model, windows, o.seed, &e);
  if (o.forecaster.forecast) e.forecasting = Forecasting(model, dataset, o);
  return e;
}

}  // namespace motionfork
