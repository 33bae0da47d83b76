// motionfork impute / ood / hgvae sample / hgvae eval: using a trained HG-VAE.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "bundle/generator_bundle.h"
#include "bundle/hgvae_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "core/error.h"
#include "dataset_loading.h"
#include "eval/metrics.h"
#include "eval/test_set.h"
#include "flags.h"
#include "generator/inference/forecaster.h"
#include "hgvae_commands.h"
#include "imputation/hgvae_experiments.h"
#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"
#include "imputation/occlusion.h"
#include "io/file_util.h"
#include "io/motion_file.h"
#include "motion_options.h"

namespace motionfork::app {
namespace {

using nlohmann::json;

// --steps / --lr / --objective over the bundle's defaults.
struct ImputeFlags {
  int steps = -1;
  double lr = 0;
  std::string objective;
  ImputeOptions Apply(ImputeOptions o) const {
    if (steps >= 0) o.steps = steps;
    if (lr > 0) o.learning_rate = lr;
    if (!objective.empty()) o.objective = ParseImputeObjective(objective);
    return o;
  }
};

void AddImputeFlags(CLI::App* cmd, ImputeFlags* f) {
  cmd->add_option("--steps", f->steps,
                  "Adam steps on the missing values (default: the bundle's, 10)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--lr", f->lr, "Adam step size on normalised coordinates (default: the bundle's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option(
         "--objective", f->objective,
         "posterior (the paper's sum over levels) or joint (+ log p(x|z)); default: the bundle's")
      ->check(CLI::IsMember({"posterior", "joint"}));
}

// ---- impute ----
struct ImputeCmd {
  std::string model, motion, out, cls;
  std::vector<std::string> masks;
  uint64_t seed = 0;
  ImputeFlags flags;
  MotionInputOptions input;
};

void RunImpute(const ImputeCmd& o, const GlobalOptions& g) {
  const HgvaeModel model = LoadHgvaeModel(o.model);
  const auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  const MotionWithGaps in =
      pipeline::LoadMotionWithGaps(o.motion, WithConfigDir(o.input, ConfigDir(g.config_dir)),
                                   skeleton, model.manifest().fps, o.masks, o.seed);
  NoteResampling(o.motion, in.resampled_from, in.motion.fps());
  const ImputeOptions options = o.flags.Apply(model.manifest().impute);
  MotionImputation r;
  try {
    r = ImputeMotion(model, in.motion, in.missing, options, model.ClassIndex(o.cls));
  } catch (const std::invalid_argument& e) {
    throw FormatError(o.motion + ": " + e.what());
  }
  WriteMotionFile(o.out, r.motion);
  const size_t total = in.missing.size();
  if (r.missing_values == 0) {
    std::printf("no missing values in %s (no NaN, no --mask): wrote it unchanged to %s\n",
                o.motion.c_str(), o.out.c_str());
    return;
  }
  double before = 0, after = 0;
  int ood_before = 0, ood_after = 0;
  for (size_t w = 0; w < r.window_starts.size(); ++w) {
    before += r.score_before[w];
    after += r.score_after[w];
    ood_before += model.OutOfDistribution(r.score_before[w]);
    ood_after += model.OutOfDistribution(r.score_after[w]);
  }
  const double n = static_cast<double>(r.window_starts.size());
  std::printf(
      "imputed %d of %zu values (%.1f%%) in %zu windows of %d frames (%d Adam steps, %s "
      "objective)\n",
      r.missing_values, total, 100.0 * r.missing_values / total, r.window_starts.size(),
      model.window(), options.steps, ToString(options.objective));
  std::printf(
      "%s score per window: %.1f with the training mean -> %.1f imputed (training windows: %.1f +- "
      "%.1f);"
      " out of distribution: %d -> %d windows\n",
      ToString(model.manifest().ood_score), before / n, after / n, model.manifest().score_mean,
      model.manifest().score_std, ood_before, ood_after);
  std::printf("wrote %s (%d frames, %.6g Hz)\n", o.out.c_str(), r.motion.num_frames(),
              r.motion.fps());
}

// ---- ood ----
struct OodCmd {
  std::string model, motion, json_out, cls;
  int stride = 0;
  MotionInputOptions input;
};

void RunOod(const OodCmd& o, GlobalOptions& g) {
  const HgvaeModel model = LoadHgvaeModel(o.model);
  const auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  const MotionWithGaps in =
      pipeline::LoadMotionWithGaps(o.motion, WithConfigDir(o.input, ConfigDir(g.config_dir)),
                                   skeleton, model.manifest().fps, {}, 0);
  NoteResampling(o.motion, in.resampled_from, in.motion.fps());
  pipeline::RequireComplete(o.motion, in.missing,
                            "impute them first ('motionfork impute'), or score the imputed file");
  std::vector<WindowScore> scores;
  try {
    scores = ScoreMotion(model, in.motion, o.stride > 0 ? o.stride : model.window(),
                         model.ClassIndex(o.cls));
  } catch (const std::invalid_argument& e) {
    throw FormatError(o.motion + ": " + e.what());
  }
  int flagged = 0;
  std::printf("window  frames       score   out of distribution (threshold %ld)\n",
              std::lround(model.OodThreshold()));
  json windows = json::array();
  for (const WindowScore& s : scores) {
    flagged += s.out_of_distribution;
    std::printf("%6zu  %5d-%-5d %9.1f   %s\n", windows.size(), s.start,
                s.start + model.window() - 1, s.score, s.out_of_distribution ? "yes" : "no");
    windows.push_back({{"start", s.start},
                       {"frames", model.window()},
                       {"score", s.score},
                       {"out_of_distribution", s.out_of_distribution}});
  }
  std::printf(
      "%d of %zu windows out of distribution (%s score below the training windows' mean %.1f - "
      "%.3g x std %.1f)\n",
      flagged, scores.size(), ToString(model.manifest().ood_score), model.manifest().score_mean,
      model.manifest().ood_k, model.manifest().score_std);
  if (!o.json_out.empty()) {
    const json j = {{"model", o.model},
                    {"motion", o.motion},
                    {"score", ToString(model.manifest().ood_score)},
                    {"threshold", model.OodThreshold()},
                    {"score_mean", model.manifest().score_mean},
                    {"score_std", model.manifest().score_std},
                    {"k", model.manifest().ood_k},
                    {"flagged", flagged},
                    {"windows", windows}};
    WriteFileAtomically(o.json_out, j.dump(2) + "\n");
  }
  g.exit_code = flagged > 0 ? 1 : 0;
}

// ---- hgvae sample ----
struct SampleCmd {
  std::string model, cls, out;
  int count = 1;
  uint64_t seed = 0;
  bool mean_latents = false;
};

void RunSample(const SampleCmd& o, const GlobalOptions&) {
  const HgvaeModel model = LoadHgvaeModel(o.model);
  const int ci = model.ClassIndex(o.cls);
  const std::vector<float> w = model.Sample(o.count, ci, o.seed, !o.mean_latents);
  const int T = model.window(), N = model.coords(), J = model.skeleton().num_joints();
  const auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  // Windows are root-relative: the root stays at the origin. Samples follow one another.
  std::vector<float> pos(static_cast<size_t>(o.count) * T * J * 3, 0.0f);
  for (size_t f = 0; f < static_cast<size_t>(o.count) * T; ++f) {
    std::copy(w.begin() + f * N, w.begin() + (f + 1) * N, pos.begin() + f * J * 3 + 3);
  }
  WriteMotionFile(o.out, Motion(skeleton, model.manifest().fps, std::move(pos)));
  std::printf(
      "wrote %s: %d sample%s of %d frames (%.6g Hz) one after another%s, root at the origin\n",
      o.out.c_str(), o.count, o.count == 1 ? "" : "s", T, model.manifest().fps,
      ci >= 0 ? (", class '" + o.cls + "'").c_str() : "");
}

// ---- hgvae eval ----
struct EvalCmd {
  std::string model, data, split_file, forecaster, json_out;
  int windows = 1000, forecast_windows = 500, k = 50;
  uint64_t seed = 0;
  bool likelihood_only = false;
  ImputeFlags flags;
};

// Test-split windows of the model's length: every window-th start of every test clip, at most
// `limit` spread evenly. [count, T, N]
std::vector<float> TestWindows(const Dataset& ds, int window, int limit) {
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
  if (count == 0)
    throw std::invalid_argument("no test clip is " + std::to_string(window) + " frames long");
  if (count <= limit) return all;
  const size_t per = all.size() / count;
  std::vector<float> out;
  for (int i = 0; i < limit; ++i) {
    const size_t w = static_cast<size_t>(i) * count / limit;
    out.insert(out.end(), all.begin() + w * per, all.begin() + (w + 1) * per);
  }
  return out;
}

double Mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

void RunEval(const EvalCmd& o, const GlobalOptions& g) {
  const HgvaeModel model = LoadHgvaeModel(o.model);
  const HgvaeManifest& m = model.manifest();
  const std::string config_dir = ConfigDir(g.config_dir);
  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", m.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", protocol.skeleton));
  const Dataset ds = LoadDatasetWithProgress(protocol, skeleton, o.data, o.split_file, g);
  const std::vector<float> windows = TestWindows(ds, model.window(), o.windows);
  const int T = model.window(), N = model.coords();
  const int count = static_cast<int>(windows.size() / (static_cast<size_t>(T) * N));
  json j = {
      {"model", o.model},
      {"protocol", m.protocol},
      {"windows", count},
      {"window_frames", T},
      {"parameters", model.num_parameters()},
      {"stochastic_levels", m.model.stochastic_levels == 0 ? static_cast<int>(m.model.levels.size())
                                                           : m.model.stochastic_levels}};
  std::printf(
      "HG-VAE %s (%s parameters, %zu levels, %d stochastic) on the %s test split: %d windows of %d "
      "frames\n",
      o.model.c_str(), WithThousands(model.num_parameters()).c_str(), m.model.levels.size(),
      j["stochastic_levels"].get<int>(), m.protocol.c_str(), count, T);

  // Likelihood: ELBO, reconstruction, KL per level.
  const HgvaeWindowFigures f = model.Evaluate(windows, o.seed);
  std::printf(
      "\nlikelihood (nats per window, densities in metres): ELBO %.1f, reconstruction MSE %.3g "
      "cm^2 "
      "(posterior means; %.3g sampled), KL",
      Mean(f.elbo), 1e4 * Mean(f.recon_mse), 1e4 * Mean(f.recon_mse_sampled));
  json kl = json::array();
  double kl_total = 0;
  for (const auto& level : f.kl_levels) {
    std::printf(" %.1f", Mean(level));
    kl.push_back(Mean(level));
    kl_total += Mean(level);
  }
  std::printf(" (total %.1f); posterior score %.1f, joint score %.1f\n", kl_total, Mean(f.score),
              Mean(f.joint_score));
  j["likelihood"] = {{"elbo_nats", Mean(f.elbo)},
                     {"recon_mse_m2", Mean(f.recon_mse)},
                     {"recon_mse_sampled_m2", Mean(f.recon_mse_sampled)},
                     {"kl_levels", kl},
                     {"kl_total", kl_total},
                     {"posterior_score_mean", Mean(f.score)},
                     {"joint_score_mean", Mean(f.joint_score)}};
  if (o.likelihood_only) {
    if (!o.json_out.empty()) WriteFileAtomically(o.json_out, j.dump(2) + "\n");
    return;
  }

  // Imputation vs mean imputation.
  const ImputeOptions options = o.flags.Apply(m.impute);
  std::vector<ImputationFigure> figs;
  {
    ProgressBar bar("imputation", !g.quiet);
    figs = ImputationExperiment(model, windows, StandardOcclusions(model.skeleton()), options,
                                o.seed, [&bar](int d, int t) { bar.Update(double(d) / t); });
  }
  std::printf("\nimputation (%d Adam steps, lr %.3g, %s objective): MSE per missing value, cm^2\n",
              options.steps, options.learning_rate, ToString(options.objective));
  std::printf("  %-12s %10s %10s %10s %10s   score mean-filled -> imputed\n", "occlusion",
              "missing", "mean", "HG-VAE", "reduction");
  json imp = json::array();
  for (const ImputationFigure& x : figs) {
    std::printf("  %-12s %10lld %10.3f %10.3f %9.1f%%   %.1f -> %.1f\n", x.occlusion.name.c_str(),
                static_cast<long long>(x.missing_values), 1e4 * x.mse_mean, 1e4 * x.mse_model,
                100 * x.reduction, x.score_before, x.score_after);
    imp.push_back({{"occlusion", x.occlusion.name},
                   {"share", x.occlusion.share},
                   {"missing_values", x.missing_values},
                   {"mse_mean_m2", x.mse_mean},
                   {"mse_hgvae_m2", x.mse_model},
                   {"reduction", x.reduction},
                   {"score_mean_filled", x.score_before},
                   {"score_imputed", x.score_after}});
  }
  j["imputation"] = {{"steps", options.steps},
                     {"learning_rate", options.learning_rate},
                     {"objective", ToString(options.objective)},
                     {"settings", imp}};

  // Out of distribution: AUROC of both scores, clean vs degraded; flagged by the bundle's score.
  const std::vector<double> clean = model.Score(windows);
  const std::vector<double> clean_post = model.Score(windows, ImputeObjective::kPosterior);
  const std::vector<double> clean_joint = model.Score(windows, ImputeObjective::kJoint);
  struct Degraded {
    std::string name;
    std::vector<float> w;
  };
  std::vector<Degraded> degraded;
  for (double s : {0.005, 0.05, 0.5}) {
    char name[64];
    std::snprintf(name, sizeof(name), "%.3g%% values -> mean", 100 * s);
    degraded.push_back({name, ReplaceWithMean(model, windows, s, o.seed + 7)});
  }
  degraded.push_back({"bones x1.5", ScaleBones(model.skeleton(), windows, 1.5f)});
  degraded.push_back({"bones x0.7", ScaleBones(model.skeleton(), windows, 0.7f)});
  degraded.push_back({"shuffled frames", ShuffleFrames(windows, N, o.seed + 11)});
  std::printf(
      "\nout of distribution: AUROC (clean vs degraded) of the joint and the posterior score; "
      "share flagged "
      "by the bundle's rule (%s score < %.1f)\n",
      ToString(m.ood_score), model.OodThreshold());
  int clean_flagged = 0;
  for (double s : clean) clean_flagged += model.OutOfDistribution(s);
  std::printf("  %-22s %12s %12s %8s\n", "windows", "AUROC joint", "posterior", "flagged");
  std::printf("  %-22s %12s %12s %7.1f%%\n", "clean", "-", "-", 100.0 * clean_flagged / count);
  json ood = json::array();
  for (const Degraded& d : degraded) {
    const std::vector<double> s = model.Score(d.w);
    int flagged = 0;
    for (double x : s) flagged += model.OutOfDistribution(x);
    const double auc_joint = Auroc(clean_joint, model.Score(d.w, ImputeObjective::kJoint));
    const double auc_post = Auroc(clean_post, model.Score(d.w, ImputeObjective::kPosterior));
    std::printf("  %-22s %12.4f %12.4f %7.1f%%\n", d.name.c_str(), auc_joint, auc_post,
                100.0 * flagged / count);
    ood.push_back({{"degradation", d.name},
                   {"auroc_joint", auc_joint},
                   {"auroc_posterior", auc_post},
                   {"flagged", double(flagged) / count}});
  }
  j["ood"] = {{"score", ToString(m.ood_score)},
              {"threshold", model.OodThreshold()},
              {"clean_flagged", double(clean_flagged) / count},
              {"tests", ood}};

  // Downstream forecasting from clean, mean-imputed and imputed histories.
  if (!o.forecaster.empty()) {
    const Forecaster fc = LoadForecaster(o.forecaster);
    if (fc.config().generator.t_his != T) {
      throw std::invalid_argument("the forecaster's history is " +
                                  std::to_string(fc.config().generator.t_his) +
                                  " frames, the HG-VAE's window " + std::to_string(T));
    }
    std::vector<const Clip*> test_clips;
    for (int c : ds.ClipIndices(Split::kTest)) test_clips.push_back(&ds.clips[c]);
    const TestSet ts = BuildTestSet(test_clips, protocol);
    const int total = ts.num_windows(), H = std::min(o.forecast_windows, total);
    const int J = ts.num_joints(), D = ts.pose_dims, P = ts.t_pred;
    std::vector<float> hist, fut;
    for (int i = 0; i < H; ++i) {
      const int w = static_cast<int>(static_cast<int64_t>(i) * total / H);
      const float* h = ts.history(w);
      for (int t = 0; t < T; ++t) {
        for (int v = 0; v < D; ++v) hist.push_back(h[(t * J + 1) * 3 + v] - h[t * J * 3 + v % 3]);
      }
      fut.insert(fut.end(), ts.future(w), ts.future(w) + static_cast<size_t>(P) * D);
    }
    ForecastRequest req;
    req.k = o.k;
    req.seed = o.seed;
    // The network's raw futures: the history is what differs, and the angle-range repair's cost
    // grows with every implausible (e.g. mean-filled) history.
    req.repair = false;
    auto score = [&](const std::vector<float>& histories) {
      const Displacement d =
          MeanMinDisplacement(fc.PredictRootRelative(histories, H, req), fut, H, o.k, P, D);
      return std::make_pair(d.ade, d.fde);
    };
    std::printf("\nforecasting (%s, K = %d, %d test windows, raw network output): ADE / FDE from\n",
                o.forecaster.c_str(), o.k, H);
    const auto clean_fc = score(hist);
    std::printf("  %-12s clean %.3f / %.3f\n", "", clean_fc.first, clean_fc.second);
    json fcj = json::array();
    const std::vector<Occlusion> settings = StandardOcclusions(model.skeleton());
    ProgressBar bar("forecasting", !g.quiet);
    for (size_t s = 0; s < settings.size(); ++s) {
      const Occlusion& oc = settings[s];
      const std::vector<uint8_t> mask = oc.share > 0
                                            ? RandomOcclusion(H, T * N, oc.share, o.seed + 99 + s)
                                            : JointOcclusion(H, T, J, oc.joints);
      const auto mean_fc = score(model.MeanImpute(hist, mask));
      const auto imp_fc = score(model.Impute(hist, mask, options).windows);
      std::printf("  %-12s mean-imputed %.3f / %.3f   HG-VAE-imputed %.3f / %.3f\n",
                  oc.name.c_str(), mean_fc.first, mean_fc.second, imp_fc.first, imp_fc.second);
      fcj.push_back({{"occlusion", oc.name},
                     {"ade_mean_imputed", mean_fc.first},
                     {"fde_mean_imputed", mean_fc.second},
                     {"ade_hgvae_imputed", imp_fc.first},
                     {"fde_hgvae_imputed", imp_fc.second}});
      bar.Update(double(s + 1) / settings.size());
    }
    bar.Finish();
    j["forecasting"] = {{"forecaster", o.forecaster},
                        {"k", o.k},
                        {"windows", H},
                        {"repair", false},
                        {"ade_clean", clean_fc.first},
                        {"fde_clean", clean_fc.second},
                        {"settings", fcj}};
  }
  if (!o.json_out.empty()) WriteFileAtomically(o.json_out, j.dump(2) + "\n");
}

}  // namespace

void AddImputeCommand(CLI::App& app, GlobalOptions& global) {
  auto o = std::make_shared<ImputeCmd>();
  CLI::App* cmd = app.add_subcommand("impute",
                                     "Fill the missing values of a motion with an HG-VAE: NaN "
                                     "values in .npy, empty or nan fields in\n"
                                     ".csv, and/or --mask. Missing values start at the training "
                                     "mean and are moved by Adam to raise\n"
                                     "the model's score (the bundle's objective); each window "
                                     "keeps its best step. Observed values\n"
                                     "are kept exactly.");
  cmd->add_option("--model", o->model,
                  "HG-VAE bundle folder (hgvae.yaml + hgvae.pt), e.g. models/bandai/hgvae")
      ->required();
  AddMotionArgument(cmd, &o->motion, "Motion file (.npy, .csv, .bvh)", "--motion");
  cmd->add_option(
      "--mask", o->masks,
      "Values to treat as missing, repeatable: random:SHARE (e.g. random:0.1), joints:A,B (every "
      "frame), joints:A,B@FIRST-LAST (0-based frames), or MASK.npy ([T, J] or [T, J, 3], non-zero "
      "= "
      "missing)");
  cmd->add_option("--class", o->cls, "Condition on this class (conditional models; default none)");
  cmd->add_option("--seed", o->seed, "Seed of random masks (default 0)");
  AddImputeFlags(cmd, &o->flags);
  cmd->add_option("-o,--out", o->out, "Output motion file (.npy, .csv or .bvh)")->required();
  AddMotionInputOptions(cmd, &o->input);
  cmd->callback([o, &global] {
    RequireMotion(o->motion);
    RunImpute(*o, global);
  });
}

void AddOodCommand(CLI::App& app, GlobalOptions& global) {
  auto o = std::make_shared<OodCmd>();
  CLI::App* cmd = app.add_subcommand("ood",
                                     "Score a motion's windows with an HG-VAE and flag those out "
                                     "of distribution: posterior score\n"
                                     "below the training windows' mean - k std (k in the bundle). "
                                     "Exit status 1 when any window is flagged.");
  cmd->add_option("--model", o->model, "HG-VAE bundle folder")->required();
  AddMotionArgument(cmd, &o->motion, "Motion file (.npy, .csv, .bvh)", "--motion");
  cmd->add_option("--stride", o->stride,
                  "Frames between window starts (default: the window length)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--class", o->cls, "Condition on this class (conditional models; default none)");
  cmd->add_option("--json", o->json_out, "Also write the scores to this JSON file");
  AddMotionInputOptions(cmd, &o->input);
  cmd->callback([o, &global] {
    RequireMotion(o->motion);
    RunOod(*o, global);
  });
}

void AddHgvaeSampleCommand(CLI::App& hgvae, GlobalOptions& global) {
  auto o = std::make_shared<SampleCmd>();
  CLI::App* cmd = hgvae.add_subcommand("sample",
                                       "Sample motion windows from an HG-VAE's prior, optionally "
                                       "of one class (conditional models).");
  cmd->add_option("--model", o->model, "HG-VAE bundle folder")->required();
  cmd->add_option("--class", o->cls, "Class to sample (e.g. walk); default none (unconditional)");
  cmd->add_option("-n,--count", o->count,
                  "Windows to sample (default 1); written one after another")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--seed", o->seed, "Random seed (default 0)");
  cmd->add_flag("--mean-latents", o->mean_latents, "Each level's prior mean instead of a sample");
  cmd->add_option("-o,--out", o->out, "Output motion file (.npy, .csv or .bvh)")->required();
  cmd->callback([o, &global] { RunSample(*o, global); });
}

void AddHgvaeEvalCommand(CLI::App& hgvae, GlobalOptions& global) {
  auto o = std::make_shared<EvalCmd>();
  CLI::App* cmd = hgvae.add_subcommand("eval",
                                       "An HG-VAE's figures on its protocol's test split: "
                                       "likelihood (ELBO, KL per level), imputation\n"
                                       "MSE vs mean imputation (random 1/10/50/90% of values, "
                                       "whole limbs), out-of-distribution AUROC,\n"
                                       "and with --forecaster the forecasting ADE/FDE from clean, "
                                       "mean-imputed and imputed histories.");
  cmd->add_option("--model", o->model, "HG-VAE bundle folder")->required();
  cmd->add_option("--data", o->data, "Data folder of the model's protocol")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--split", o->split_file, "Split file overriding the protocol's");
  cmd->add_option("--windows", o->windows, "Test windows, spread evenly (default 1000)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--forecaster", o->forecaster,
                  "Generator bundle for the downstream figures (e.g. models/bandai)");
  cmd->add_option("--forecast-windows", o->forecast_windows,
                  "Protocol test windows for them (default 500)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("-k", o->k, "Futures per history (default 50)")->check(CLI::PositiveNumber);
  cmd->add_option("--seed", o->seed, "Seed of masks and samples (default 0)");
  cmd->add_flag("--likelihood-only", o->likelihood_only, "Only the likelihood figures");
  AddImputeFlags(cmd, &o->flags);
  cmd->add_option("--json", o->json_out, "Also write every figure to this JSON file");
  cmd->callback([o, &global] { RunEval(*o, global); });
}

}  // namespace motionfork::app
