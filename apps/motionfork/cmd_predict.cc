// motionfork predict: K futures of a history with a trained model bundle.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>

#include "app_common.h"
#include "bundle/dvae_bundle.h"
#include "bundle/hgvae_bundle.h"
#include "commands.h"
#include "core/error.h"
#include "core/resample.h"
#include "denoise/denoise_metrics.h"
#include "denoise/dvae_model.h"
#include "generator/inference/forecaster.h"
#include "hgvae_input.h"
#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"
#include "io/file_util.h"
#include "io/prediction_file.h"
#include "motion_options.h"
#include "validity/pose_validator.h"

namespace motionfork::app {
namespace {

struct PredictOptions {
  std::string model;
  std::string history;
  int start = -1;
  int k = 50;
  std::vector<std::string> fix;
  uint64_t seed = 0;
  bool no_repair = false;
  std::string impute;              // HG-VAE bundle filling the history's missing values
  std::vector<std::string> masks;  // extra missing values (--mask), with --impute
  std::string denoise;             // Motion-DVAE bundle denoising the history
  std::string out;
  MotionInputOptions input;
};

// Denoises the history frames [start, start + t_his) of *history with the Motion-DVAE in `dir`,
// together with up to one model window of frames before them (never a frame after them).
HistoryDenoising DenoiseHistory(const std::string& dir, const std::string& file, int start,
                                int t_his, Motion* history) {
  const DvaeModel dv = LoadDvaeModel(dir);
  if (dv.skeleton().joint_names() != history->skeleton().joint_names() ||
      std::abs(dv.manifest().fps - history->fps()) > 1e-6 * history->fps()) {
    throw FormatError(dir + ": the Motion-DVAE (skeleton '" + dv.skeleton().name() + "', " +
                      std::to_string(dv.manifest().fps) +
                      " Hz) does not match the forecaster's (skeleton '" +
                      history->skeleton().name() + "', " + std::to_string(history->fps()) + " Hz)");
  }
  const int end = start + t_his, first = std::max(0, end - std::max(dv.window(), t_his));
  const Motion context = history->Slice(first, end);
  Motion clean;
  try {
    clean = DenoiseMotion(dv, context, dv.manifest().denoise);
  } catch (const std::invalid_argument& e) {
    throw FormatError(file + ": " + e.what());
  }
  const size_t fv = static_cast<size_t>(history->num_joints()) * 3;
  std::vector<float> pos = history->positions();
  const std::vector<float> before(pos.begin() + start * fv, pos.begin() + end * fv);
  std::copy(clean.positions().begin() + (start - first) * fv, clean.positions().end(),
            pos.begin() + start * fv);
  const std::vector<float> after(pos.begin() + start * fv, pos.begin() + end * fv);
  *history = Motion(history->skeleton_ptr(), history->fps(), std::move(pos));
  HistoryDenoising d{dir, ToString(dv.manifest().denoise.mode), end - first,
                     MeanJointError(before, after)};
  std::printf(
      "denoised the history with %s (%s mode, frames %d..%d): mean change %.2f cm per joint\n",
      dir.c_str(), d.mode.c_str(), first, end - 1, 100 * d.mean_change);
  return d;
}

void RunPredict(const PredictOptions& o, const GlobalOptions& g) {
  const Forecaster model = Forecaster::Load(o.model);
  const ModelConfig& mc = model.config();
  // Read the history (missing values allowed); put it on the model's skeleton and frame rate.
  if (o.impute.empty() && !o.masks.empty())
    throw FormatError("--mask needs --impute (an HG-VAE bundle to fill the values)");
  MotionWithGaps gaps = LoadMotionWithGaps(o.history, o.input, ConfigDir(g.config_dir),
                                           model.skeleton(), mc.fps, o.masks, o.seed);
  Motion history = gaps.motion;
  const int t_his = mc.generator.t_his;
  const int frames = history.num_frames();
  if (frames < t_his || (o.start >= 0 && o.start + t_his > frames)) {
    char need[160];
    std::snprintf(need, sizeof(need), "the model needs %d history frames (%.3g s at %.6g Hz)",
                  t_his, t_his / mc.fps, mc.fps);
    throw FormatError(o.history + ": " + need +
                      (o.start >= 0 ? ", frames " + std::to_string(o.start) + ".." +
                                          std::to_string(o.start + t_his - 1) + " with --start " +
                                          std::to_string(o.start)
                                    : std::string()) +
                      "; the motion has " + std::to_string(frames) + " frames");
  }
  const int start = o.start >= 0 ? o.start : frames - t_his;
  const size_t frame_values = static_cast<size_t>(history.num_joints()) * 3;
  std::vector<uint8_t> missing(gaps.missing.begin() + start * frame_values,
                               gaps.missing.begin() + (start + t_his) * frame_values);
  const int num_missing = static_cast<int>(std::count(missing.begin(), missing.end(), 1));
  std::optional<HistoryImputation> imputation;
  if (num_missing > 0) {
    if (o.impute.empty()) {
      throw FormatError(o.history + ": the history (frames " + std::to_string(start) + ".." +
                        std::to_string(start + t_his - 1) + ") has " + std::to_string(num_missing) +
                        " missing values; pass --impute DIR (an HG-VAE bundle, e.g. "
                        "models/bandai/hgvae) to fill them");
    }
    const HgvaeModel hg = LoadHgvaeModel(o.impute);
    if (hg.skeleton().joint_names() != model.skeleton()->joint_names() || hg.window() != t_his ||
        std::abs(hg.manifest().fps - mc.fps) > 1e-6 * mc.fps) {
      throw FormatError(
          o.impute + ": the HG-VAE (skeleton '" + hg.skeleton().name() + "', windows of " +
          std::to_string(hg.window()) + " frames at " + std::to_string(hg.manifest().fps) +
          " Hz) does not match the forecaster's history (" + std::to_string(t_his) + " frames at " +
          std::to_string(mc.fps) + " Hz, skeleton '" + model.skeleton()->name() + "')");
    }
    MotionImputation r;
    try {
      r = ImputeMotion(hg, history.Slice(start, start + t_his), missing, hg.manifest().impute);
    } catch (const std::invalid_argument& e) {
      throw FormatError(o.history + ": " + e.what());
    }
    std::vector<float> pos = history.positions();
    std::copy(r.motion.positions().begin(), r.motion.positions().end(),
              pos.begin() + start * frame_values);
    history = Motion(history.skeleton_ptr(), history.fps(), std::move(pos));
    imputation =
        HistoryImputation{o.impute, num_missing, r.score_before.at(0), r.score_after.at(0)};
    std::printf(
        "imputed %d missing history values with %s (%s score %.1f -> %.1f; training windows %.1f "
        "+- %.1f)\n",
        num_missing, o.impute.c_str(), ToString(hg.manifest().ood_score), imputation->score_before,
        imputation->score_after, hg.manifest().score_mean, hg.manifest().score_std);
  }
  std::optional<HistoryDenoising> denoising;
  if (!o.denoise.empty()) denoising = DenoiseHistory(o.denoise, o.history, start, t_his, &history);
  ForecastRequest req;
  req.k = o.k;
  req.seed = o.seed;
  req.fixed_parts = o.fix;
  req.repair = !o.no_repair;
  const Forecast f = model.Predict(history, start, req);

  // Each sample: the history followed by its future, [K, t_his + t_pred, J, 3].
  Prediction p;
  p.model = o.model;
  p.protocol = mc.protocol;
  p.history = o.history;
  p.start_frame = start;
  p.k = f.k;
  p.t_his = f.t_his;
  p.t_pred = f.t_pred;
  p.seed = o.seed;
  p.fps = f.fps;
  p.skeleton = model.skeleton();
  p.fixed_parts = o.fix;
  p.imputation = imputation;
  p.denoising = denoising;
  const size_t future_size = static_cast<size_t>(f.t_pred) * f.joints * 3;
  for (int k = 0; k < f.k; ++k) {
    p.positions.insert(p.positions.end(), f.history.begin(), f.history.end());
    p.positions.insert(p.positions.end(), f.futures.begin() + k * future_size,
                       f.futures.begin() + (k + 1) * future_size);
  }
  // Plausibility of every future (and of the history, for reference) with the bundle's own
  // constraint set and prior, when it carries them.
  const PoseValidator validator = PoseValidator::FromBundle(o.model, model.skeleton(), mc.fps);
  int valid = 0;
  double nll_sum = 0;
  if (validator.has_constraints() || validator.has_prior()) {
    p.history_validity = validator.Score(f.history.data(), f.t_his);
    for (int k = 0; k < f.k; ++k) {
      p.samples.push_back(validator.Score(f.futures.data() + k * future_size, f.t_pred));
      valid += p.samples.back().valid;
      nll_sum += p.samples.back().prior_nll.value_or(0.0);
    }
  }
  const std::string base = WritePrediction(o.out, p);
  std::printf("wrote %s.npy [%d, %d, %d, 3] (history + %d futures, %.6g Hz) and %s.json\n",
              base.c_str(), f.k, p.frames(), f.joints, f.k, f.fps, base.c_str());
  if (validator.has_constraints()) {
    std::printf(
        "angle ranges: %d of %d futures valid in every frame (history: %d of %d frames violate)\n",
        valid, f.k, p.history_validity->violating_frames, f.t_his);
  }
  if (validator.has_prior()) {
    std::printf("prior NLL: futures %.2f nats per pose (mean), history %.2f\n", nll_sum / f.k,
                *p.history_validity->prior_nll);
  }
  if (!validator.has_constraints() && !validator.has_prior()) {
    std::printf("no validity figures: the bundle carries no constraints.yaml or prior/\n");
  }
}

}  // namespace

void AddPredictCommand(CLI::App& app, GlobalOptions& global) {
  auto o = std::make_shared<PredictOptions>();
  CLI::App* cmd = app.add_subcommand(
      "predict",
      "Predict K futures of a history with a trained model bundle.\n"
      "Writes OUT.npy [K, t_his + t_pred, J, 3] (each sample: the history, then its future; "
      "metres;\n"
      "the root stays where the history ended: models predict root-relative poses) and OUT.json\n"
      "(skeleton, parts, and per sample: angle-range validity and mean prior NLL of its future).");
  cmd->add_option("--model", o->model, "Model bundle folder (model.yaml + generator.pt)")
      ->required();
  cmd->add_option("--history", o->history, "Motion file holding the history (.bvh, .npy, .csv)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--start", o->start,
                  "First history frame (default: the last t_his frames of the file)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("-k", o->k, "Futures to predict (default 50)")->check(CLI::PositiveNumber);
  cmd->add_option("--fix", o->fix,
                  "Body part whose latent all K futures share (e.g. legs: same legs, varied upper "
                  "body); repeat for several");
  cmd->add_option("--seed", o->seed,
                  "Random seed: the same seed gives the same futures (default 0)");
  cmd->add_flag("--no-repair", o->no_repair,
                "Keep the network's raw futures: by default poses that break the bundle's angle "
                "ranges (constraints.yaml) are moved back inside them, as little as it takes");
  cmd->add_option(
      "--impute", o->impute,
      "HG-VAE bundle (e.g. models/bandai/hgvae) filling the history's missing values: NaN in .npy, "
      "empty or nan fields in .csv, and --mask");
  cmd->add_option(
      "--mask", o->masks,
      "With --impute: values to treat as missing, repeatable: random:SHARE, joints:A,B or "
      "joints:A,B@FIRST-LAST");
  cmd->add_option("--denoise", o->denoise,
                  "Motion-DVAE bundle (e.g. models/bandai/dvae) denoising the history first (after "
                  "--impute), with\n"
                  "up to one model window of earlier frames as context");
  cmd->add_option("-o,--out", o->out, "Output path (OUT.npy and OUT.json are written)")->required();
  AddMotionInputOptions(cmd, &o->input);
  cmd->callback([o, &global] { RunPredict(*o, global); });
}

}  // namespace motionfork::app
