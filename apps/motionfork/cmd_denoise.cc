// motionfork denoise / dvae eval: using a trained Motion-DVAE denoiser.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>

#include "app_common.h"
#include "bundle/dvae_bundle.h"
#include "bundle/generator_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "core/error.h"
#include "core/motion_noise.h"
#include "dataset_loading.h"
#include "denoise/denoise_metrics.h"
#include "denoise/dvae_model.h"
#include "dvae_commands.h"
#include "eval/metrics.h"
#include "eval/test_set.h"
#include "flags.h"
#include "generator/inference/forecaster.h"
#include "io/file_util.h"
#include "io/motion_file.h"
#include "motion_options.h"
#include "torch_util/threads.h"

namespace motionfork::app {
namespace {

using nlohmann::json;

// --mode / --iterations / --samples / --seed over the bundle's defaults.
struct DenoiseFlags {
  std::string mode;
  int iterations = -1, samples = -1;
  int64_t seed = -1;
  std::string output;
  DenoiseOptions Apply(DenoiseOptions o) const {
    if (!mode.empty()) o.mode = ParseDenoiseMode(mode);
    if (iterations >= 0) o.iterations = iterations;
    if (samples >= 0) o.samples = samples;
    if (seed >= 0) o.seed = static_cast<uint64_t>(seed);
    if (!output.empty()) o.fuse = output == "fused";
    return o;
  }
};

void AddDenoiseFlags(CLI::App* cmd, DenoiseFlags* f) {
  cmd->add_option("--mode", f->mode,
                  "regression (one pass of the fine-tuned encoder) or optimisation (Adam steps on "
                  "the sequence's\n"
                  "own loss first); default: the bundle's")
      ->check(CLI::IsMember({"regression", "optimisation", "optimization"}));
  cmd->add_option("--iterations", f->iterations,
                  "Optimisation mode: Adam steps (default: the bundle's, 50)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--samples", f->samples,
                  "Posterior draws averaged; 0 = posterior means (default: the bundle's)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", f->seed, "Seed of the posterior draws (default: the bundle's)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--blend", f->output,
                  "fused (the paper's: decoder and input weighted by their variances) or decoder "
                  "(the decoder's\n"
                  "frames alone, smoother); default: the bundle's")
      ->check(CLI::IsMember({"fused", "decoder"}));
  AddDeprecatedOption(cmd, "--output", "--blend", &f->output);
}

// ---- denoise ----
struct DenoiseCmd {
  std::string model, motion, out, noise;
  uint64_t noise_seed = 0;
  int threads = 1;
  DenoiseFlags flags;
  MotionInputOptions input;
};

void RunDenoise(const DenoiseCmd& o, const GlobalOptions& g) {
  PinThreads(o.threads);
  const DvaeModel model = LoadDvaeModel(o.model);
  const auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  const MotionWithGaps in =
      pipeline::LoadMotionWithGaps(o.motion, WithConfigDir(o.input, ConfigDir(g.config_dir)),
                                   skeleton, model.manifest().fps, {}, 0);
  NoteResampling(o.motion, in.resampled_from, in.motion.fps());
  pipeline::RequireComplete(o.motion, in.missing,
                            "fill them first ('motionfork impute'), then denoise");
  Motion motion = in.motion;
  if (!o.noise.empty()) {
    NoiseSpec spec;
    try {
      spec = ParseNoiseSpec(o.noise);
    } catch (const std::invalid_argument& e) {
      throw FormatError(std::string("--add-noise: ") + e.what());
    }
    motion = AddNoise(motion, spec, o.noise_seed);
    std::printf("added %s noise (seed %llu) before denoising\n", o.noise.c_str(),
                static_cast<unsigned long long>(o.noise_seed));
  }
  if (motion.num_frames() < 2)
    throw FormatError(o.motion + ": expected at least 2 frames, found " +
                      std::to_string(motion.num_frames()));
  const DenoiseOptions options = o.flags.Apply(model.manifest().denoise);
  DenoiseStats stats;
  Motion out;
  try {
    ProgressBar bar(std::string("denoising (") + ToString(options.mode) + ")", !g.quiet);
    out = DenoiseMotion(model, motion, options, &stats, [&bar](double f) { bar.Update(f); });
    bar.Finish();
  } catch (const std::invalid_argument& e) {
    throw FormatError(o.motion + ": " + e.what());
  }
  WriteMotionFile(o.out, out);
  const double moved = MeanJointError(motion.positions(), out.positions());
  std::printf(
      "denoised %d frames (%d window%s of <= %d frames, %s mode%s) in %.3f s (%.0f frames/s); "
      "mean change %.2f cm per joint\n",
      out.num_frames(), stats.windows, stats.windows == 1 ? "" : "s", model.window(),
      ToString(options.mode),
      options.mode == DenoiseMode::kOptimisation
          ? (", " + std::to_string(options.iterations) + " iterations").c_str()
          : "",
      stats.seconds, out.num_frames() / std::max(1e-9, stats.seconds), 100 * moved);
  if (!o.noise.empty()) {
    std::printf("against the file before --add-noise: noisy %.2f cm, denoised %.2f cm per joint\n",
                100 * MeanJointError(motion.positions(), in.motion.positions()),
                100 * MeanJointError(out.positions(), in.motion.positions()));
  }
  std::printf("noise model's typical std per joint (cm):");
  for (int j = 0; j < model.joints(); ++j) {
    std::printf(" %s %.1f", model.skeleton().joint_names()[j].c_str(), 100 * stats.noise_std[j]);
  }
  std::printf("\nwrote %s (%d frames, %.6g Hz)\n", o.out.c_str(), out.num_frames(), out.fps());
}

// ---- dvae eval ----
struct EvalCmd {
  std::string model, data, split_file, forecaster, json_out;
  std::vector<std::string> noises = {"gaussian:0.02",    "gaussian:0.05",     "gaussian:0.10",
                                     "outliers:0.1,0.3", "outliers:0.05,0.5", "jitter:0.05"};
  int clips = 200, optimisation_clips = 20, forecast_windows = 300, k = 50, threads = 1;
  double smooth_sigma = 2.0;
  uint64_t seed = 0;
  DenoiseFlags flags;
};

struct Figures {
  double err = 0, accel = 0;
};

Figures Measure(const std::vector<std::vector<float>>& out,
                const std::vector<std::vector<float>>& clean, int J, double fps) {
  Figures f;
  double frames = 0;
  for (size_t c = 0; c < out.size(); ++c) {
    const double n = static_cast<double>(out[c].size() / (3 * J));
    f.err += MeanJointError(out[c], clean[c]) * n;
    f.accel += MeanAcceleration(out[c], J, fps) * n;
    frames += n;
  }
  f.err /= frames;
  f.accel /= frames;
  return f;
}

void RunEval(const EvalCmd& o, const GlobalOptions& g) {
  PinThreads(o.threads);
  const DvaeModel model = LoadDvaeModel(o.model);
  const DvaeManifest& m = model.manifest();
  const std::string config_dir = ConfigDir(g.config_dir);
  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", m.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", protocol.skeleton));
  const Dataset ds = LoadDatasetWithProgress(protocol, skeleton, o.data, o.split_file, g);
  const int J = model.joints();
  const double fps = m.fps;
  std::vector<int> test = ds.ClipIndices(Split::kTest);
  if (test.empty()) throw std::invalid_argument(o.data + ": the protocol's test split is empty");
  std::vector<std::vector<float>> clean;
  for (int i = 0; i < std::min<int>(o.clips, static_cast<int>(test.size())); ++i) {
    clean.push_back(ds.clips[test[static_cast<size_t>(i) * test.size() /
                                  std::min<int>(o.clips, static_cast<int>(test.size()))]]
                        .motion.positions());
  }
  const int opt_clips = std::min<int>(o.optimisation_clips, static_cast<int>(clean.size()));
  size_t frames = 0, opt_frames = 0;
  for (size_t c = 0; c < clean.size(); ++c) {
    frames += clean[c].size() / (3 * J);
    if (static_cast<int>(c) < opt_clips) opt_frames += clean[c].size() / (3 * J);
  }
  const double clean_accel = Measure(clean, clean, J, fps).accel;
  DenoiseOptions reg = o.flags.Apply(m.denoise);
  reg.mode = DenoiseMode::kRegression;
  DenoiseOptions opt = reg;
  opt.mode = DenoiseMode::kOptimisation;
  std::printf(
      "Motion-DVAE %s (%s parameters%s), %zu test clips (%s frames, style '%s' unseen in "
      "training);\n"
      "clean acceleration %.2f m/s^2; %d posterior draws; optimisation mode on the first %d clips "
      "(%s frames), %d iterations\n",
      o.model.c_str(), WithThousands(model.num_parameters()).c_str(),
      m.finetuned ? ", fine-tuned on noisy data" : ", prior only", clean.size(),
      WithThousands(frames).c_str(), ds.clips[test[0]].subject.c_str(), clean_accel, reg.samples,
      opt_clips, WithThousands(opt_frames).c_str(), opt.iterations);
  std::printf(
      "\n%-18s %9s %9s %8s %9s %9s %8s   accel / clean: noisy  smooth  denoised  optimised\n",
      "noise (cm error)", "noisy", "smooth", "denoised", "removed", "optimised", "removed");
  json rows = json::array();
  double reg_seconds = 0, opt_seconds = 0;
  ProgressBar bar("noise settings", !g.quiet);
  for (size_t n = 0; n < o.noises.size(); ++n) {
    const NoiseSpec spec = ParseNoiseSpec(o.noises[n]);
    std::vector<std::vector<float>> noisy = clean, smooth;
    std::mt19937_64 rng(o.seed + 1000 * n);
    for (auto& q : noisy) AddNoise(spec, q.data(), static_cast<int>(q.size() / (3 * J)), J, rng);
    for (const auto& q : noisy) smooth.push_back(GaussianSmooth(q, J, o.smooth_sigma));
    DenoiseStats st, st_opt;
    const auto denoised = model.Denoise(noisy, reg, &st);
    reg_seconds += st.seconds;
    const Figures fn = Measure(noisy, clean, J, fps), fs = Measure(smooth, clean, J, fps),
                  fd = Measure(denoised, clean, J, fps);
    Figures fo{NAN, NAN}, fon{NAN, NAN};
    if (opt_clips > 0) {
      const std::vector<std::vector<float>> opt_in(noisy.begin(), noisy.begin() + opt_clips),
          opt_clean(clean.begin(), clean.begin() + opt_clips);
      fo = Measure(model.Denoise(opt_in, opt, &st_opt), opt_clean, J, fps);
      fon = Measure(opt_in, opt_clean, J, fps);
      opt_seconds += st_opt.seconds;
    }
    const double removed = 1 - fd.err / fn.err, removed_opt = 1 - fo.err / fon.err;
    auto num = [](double v, const char* format) {
      char buf[32];
      std::snprintf(buf, sizeof(buf), format, v);
      return std::isfinite(v) ? std::string(buf) : std::string("-");
    };
    std::printf("%-18s %9.2f %9.2f %8.2f %9s %9s %8s   %19.2f %7.2f %9.2f %10s\n",
                o.noises[n].c_str(), 100 * fn.err, 100 * fs.err, 100 * fd.err,
                num(100 * removed, "%.1f%%").c_str(), num(100 * fo.err, "%.2f").c_str(),
                num(100 * removed_opt, "%.1f%%").c_str(), fn.accel / clean_accel,
                fs.accel / clean_accel, fd.accel / clean_accel,
                num(fo.accel / clean_accel, "%.2f").c_str());
    std::fflush(stdout);
    rows.push_back({{"noise", o.noises[n]},
                    {"noisy_cm", 100 * fn.err},
                    {"smooth_cm", 100 * fs.err},
                    {"denoised_cm", 100 * fd.err},
                    {"removed", removed},
                    {"optimised_cm", 100 * fo.err},
                    {"optimised_noisy_cm", 100 * fon.err},
                    {"removed_optimised", removed_opt},
                    {"smooth_removed", 1 - fs.err / fn.err},
                    {"accel_ratio_noisy", fn.accel / clean_accel},
                    {"accel_ratio_smooth", fs.accel / clean_accel},
                    {"accel_ratio_denoised", fd.accel / clean_accel},
                    {"accel_ratio_optimised", fo.accel / clean_accel}});
    bar.Update(double(n + 1) / o.noises.size());
  }
  bar.Finish();
  const double reg_fps = frames * o.noises.size() / reg_seconds,
               opt_fps = opt_frames * o.noises.size() / opt_seconds;
  std::printf(
      "(smooth: Gaussian over time, sigma %.3g frames, a baseline; optimised: on the first %d "
      "clips, against\n"
      "their own noisy error)\nspeed on %d thread(s): regression %.0f frames/s",
      o.smooth_sigma, opt_clips, o.threads, reg_fps);
  if (opt_clips > 0)
    std::printf(", optimisation %.0f frames/s (%d iterations per sequence)", opt_fps,
                opt.iterations);
  std::printf("\n");
  json j = {{"model", o.model},
            {"clips", clean.size()},
            {"frames", frames},
            {"clean_accel", clean_accel},
            {"samples", reg.samples},
            {"iterations", opt.iterations},
            {"optimisation_clips", opt_clips},
            {"regression_frames_per_s", reg_fps},
            {"settings", rows}};
  if (opt_clips > 0) j["optimisation_frames_per_s"] = opt_fps;

  // Downstream: forecasting from noisy vs denoised histories. Each history is denoised with the
  // window() frames that end with it (no future frame is seen).
  if (!o.forecaster.empty()) {
    const Forecaster fc = LoadForecaster(o.forecaster);
    if (fc.config().generator.t_his != protocol.t_his ||
        fc.skeleton()->joint_names() != model.skeleton().joint_names()) {
      throw std::invalid_argument(o.forecaster + ": the forecaster's history (" +
                                  std::to_string(fc.config().generator.t_his) +
                                  " frames, skeleton '" + fc.skeleton()->name() +
                                  "') does not match the protocol '" + protocol.name +
                                  "' of the Motion-DVAE");
    }
    std::vector<const Clip*> test_clips;
    for (int c : test) test_clips.push_back(&ds.clips[c]);
    const TestSet ts = BuildTestSet(test_clips, protocol);
    const int total = ts.num_windows(), H = std::min(o.forecast_windows, total);
    const int T = ts.t_his, D = ts.pose_dims, P = ts.t_pred, W = model.window();
    std::vector<float> fut;
    std::vector<std::pair<int, int>> picks;  // (window, context start)
    for (int i = 0; i < H; ++i) {
      const int w = static_cast<int>(static_cast<int64_t>(i) * total / H);
      const int end = ts.windows[w].start + T;
      picks.emplace_back(w, std::max(0, end - W));
      fut.insert(fut.end(), ts.future(w), ts.future(w) + static_cast<size_t>(P) * D);
    }
    auto to_history = [&](const std::vector<std::vector<float>>& contexts) {
      std::vector<float> hist;
      for (const auto& q : contexts) {
        const int n = static_cast<int>(q.size() / (3 * J));
        for (int t = n - T; t < n; ++t) {
          const float* f = q.data() + static_cast<size_t>(t) * J * 3;
          for (int v = 0; v < D; ++v) hist.push_back(f[3 + v] - f[v % 3]);
        }
      }
      return hist;
    };
    ForecastRequest req;
    req.k = o.k;
    req.seed = o.seed;
    req.repair = false;
    auto score = [&](const std::vector<float>& histories) {
      const Displacement d =
          MeanMinDisplacement(fc.PredictRootRelative(histories, H, req), fut, H, o.k, P, D);
      return std::make_pair(d.ade, d.fde);
    };
    std::vector<std::vector<float>> contexts;
    for (const auto& [w, s] : picks) {
      const Motion& mo = test_clips[ts.windows[w].clip]->motion;
      const std::vector<float>& p = mo.positions();
      contexts.emplace_back(p.begin() + static_cast<size_t>(s) * J * 3,
                            p.begin() + static_cast<size_t>(ts.windows[w].start + T) * J * 3);
    }
    const auto clean_fc = score(to_history(contexts));
    std::printf(
        "\nforecasting (%s, K = %d, %d test windows, raw network output): ADE / FDE, clean history "
        "%.3f / %.3f\n",
        o.forecaster.c_str(), o.k, H, clean_fc.first, clean_fc.second);
    json fcj = json::array();
    for (size_t n = 0; n < o.noises.size(); ++n) {
      const NoiseSpec spec = ParseNoiseSpec(o.noises[n]);
      std::vector<std::vector<float>> noisy = contexts;
      std::mt19937_64 rng(o.seed + 7777 + n);
      for (auto& q : noisy) AddNoise(spec, q.data(), static_cast<int>(q.size() / (3 * J)), J, rng);
      const auto noisy_fc = score(to_history(noisy));
      const auto den_fc = score(to_history(model.Denoise(noisy, reg)));
      std::printf("  %-18s noisy %.3f / %.3f   denoised %.3f / %.3f\n", o.noises[n].c_str(),
                  noisy_fc.first, noisy_fc.second, den_fc.first, den_fc.second);
      fcj.push_back({{"noise", o.noises[n]},
                     {"ade_noisy", noisy_fc.first},
                     {"fde_noisy", noisy_fc.second},
                     {"ade_denoised", den_fc.first},
                     {"fde_denoised", den_fc.second}});
    }
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

void AddDenoiseCommand(CLI::App& app, GlobalOptions& global) {
  auto d = std::make_shared<DenoiseCmd>();
  CLI::App* cmd = app.add_subcommand(
      "denoise",
      "Denoise a motion file (estimated, noisy joint positions) with a Motion-DVAE bundle, e.g.\n"
      "models/bandai/dvae. Windows of the model's length every 'stride' frames, blended.");
  cmd->add_option("--model", d->model, "Motion-DVAE bundle folder")
      ->required()
      ->check(CLI::ExistingDirectory);
  AddMotionArgument(cmd, &d->motion, "Motion file (.npy, .csv, .bvh, .npz)", "--motion");
  cmd->add_option("-o,--out", d->out, "Output motion file (format from the extension)")->required();
  cmd->add_option(
      "--add-noise", d->noise,
      "Corrupt the input first (a test): gaussian:S, outliers:P,S or jitter:S (metres)");
  cmd->add_option("--noise-seed", d->noise_seed, "Seed of --add-noise (default 0)");
  cmd->add_option("--threads", d->threads, "Threads (default 1)")->check(CLI::PositiveNumber);
  AddDenoiseFlags(cmd, &d->flags);
  AddMotionInputOptions(cmd, &d->input);
  cmd->callback([d, &global] {
    RequireMotion(d->motion);
    RunDenoise(*d, global);
  });
}

void AddDvaeEvalCommand(CLI::App& dvae, GlobalOptions& global) {
  auto e = std::make_shared<EvalCmd>();
  CLI::App* cmd = dvae.add_subcommand("eval",
                                      "Denoising figures on a protocol's test split: error of "
                                      "noisy, smoothed (baseline), denoised\n"
                                      "(regression mode) and optimised (optimisation mode) motion "
                                      "against the clean one for each noise\n"
                                      "kind, acceleration against the clean motion's, speed, and "
                                      "with --forecaster the forecasting\n"
                                      "ADE/FDE from noisy and denoised histories.");
  cmd->add_option("--model", e->model, "Motion-DVAE bundle folder")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--data", e->data, "Data folder of the bundle's protocol")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--split", e->split_file, "Split file overriding the protocol's");
  cmd->add_option(
      "--noise", e->noises,
      "Noise kinds (repeatable; default: gaussian 2/5/10 cm, two outlier settings, jitter 5 cm)");
  cmd->add_option("--clips", e->clips, "Test clips used, spread evenly (default 200)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--optimisation-clips", e->optimisation_clips,
                  "Of those, how many optimisation mode runs on (default 20)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--smooth-sigma", e->smooth_sigma,
                  "Baseline's Gaussian sigma in frames (default 2)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--forecaster", e->forecaster,
                  "Generator bundle for the downstream figures (e.g. models/bandai)");
  cmd->add_option("--forecast-windows", e->forecast_windows,
                  "Protocol test windows forecast (default 300)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("-k", e->k, "Futures per history (default 50)")->check(CLI::PositiveNumber);
  cmd->add_option("--threads", e->threads, "Threads (default 1)")->check(CLI::PositiveNumber);
  cmd->add_option("--json", e->json_out, "Write the figures as JSON");
  AddDenoiseFlags(cmd, &e->flags);
  cmd->callback([e, &global] { RunEval(*e, global); });
}

}  // namespace motionfork::app
