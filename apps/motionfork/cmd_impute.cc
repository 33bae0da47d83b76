// motionfork impute / ood / hgvae sample / hgvae eval: using a trained HG-VAE.
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "bundle/hgvae_bundle.h"
#include "commands.h"
#include "core/error.h"
#include "experiment_common.h"
#include "flags.h"
#include "generator/training/history_forecaster.h"
#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"
#include "imputation/motion_imputation_json.h"
#include "imputation/motion_imputation_summary.h"
#include "imputation/motion_imputation_text.h"
#include "imputation/motion_sampling.h"
#include "imputation/training/hgvae_evaluation.h"
#include "imputation/training/hgvae_evaluation_json.h"
#include "imputation/training/hgvae_evaluation_text.h"
#include "io/motion_file.h"
#include "motion_options.h"
#include "torch_util/threads.h"

namespace motionfork::app {
namespace {

void AddImputeOverrides(CLI::App* cmd, ImputeOverrides* f) {
  cmd->add_option("--steps", f->steps,
                  "Adam steps on the missing values (default: the bundle's, 10)")
      ->check(NonNegativeNumber);
  cmd->add_option("--lr", f->learning_rate,
                  "Adam step size on normalised coordinates (default: the bundle's)")
      ->check(PositiveNumber);
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
  ImputeOverrides flags;
  MotionInputOptions input;
};

void RunImpute(const ImputeCmd& o, const GlobalOptions& g) {
  RequireMotion(o.motion);
  const HgvaeModel model = LoadHgvaeModel(o.model);
  const MotionWithGaps in =
      LoadMotionForModel(o.motion, o.input, g, model.skeleton(), model.manifest().fps,
                         model.manifest().protocol, o.masks, o.seed);
  const ImputeOptions options = o.flags.Apply(model.manifest().impute);
  MotionImputation r;
  try {
    r = ImputeMotion(model, in.motion, in.missing, options, model.ClassIndex(o.cls));
  } catch (const std::invalid_argument& e) {
    throw FormatError(o.motion + ": " + e.what());
  }
  WriteMotionFile(o.out, r.motion);
  PrintText(MotionImputationText(model, r, in.missing.size(), options, o.motion, o.out));
}

// ---- ood ----
struct OodCmd {
  std::string model, motion, json_out, cls;
  int stride = 0;
  MotionInputOptions input;
};

void RunOod(const OodCmd& o, GlobalOptions& g) {
  RequireMotion(o.motion);
  const HgvaeModel model = LoadHgvaeModel(o.model);
  const MotionWithGaps in = LoadMotionForModel(o.motion, o.input, g, model.skeleton(),
                                               model.manifest().fps, model.manifest().protocol);
  pipeline::RequireComplete(o.motion, in.missing,
                            "impute them first ('motionfork impute'), or score the imputed file");
  std::vector<WindowScore> scores;
  try {
    scores = ScoreMotion(model, in.motion, o.stride > 0 ? o.stride : model.window(),
                         model.ClassIndex(o.cls));
  } catch (const std::invalid_argument& e) {
    throw FormatError(o.motion + ": " + e.what());
  }
  const int flagged = CountOutOfDistribution(scores);
  PrintText(WindowScoresText(model, scores));
  EmitJson(o.json_out, WindowScoresJson(model, scores, o.model, o.motion));
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
  WriteMotionFile(o.out, SampleMotion(model, o.count, ci, o.seed, !o.mean_latents));
  PrintText(SampledMotionText(model, o.count, o.cls, o.out));
}

// ---- hgvae eval ----
struct EvalCmd {
  std::string model, data, split_file, forecaster, json_out;
  int threads = 0;
  HgvaeEvalOptions eval;
  ImputeOverrides flags;
};

void RunEval(EvalCmd o, const GlobalOptions& g) {
  HgvaeModel model = LoadHgvaeModel(o.model);
  model.set_threads(WindowThreads(o.threads));
  const HgvaeManifest& m = model.manifest();
  const Dataset ds = LoadProtocolDataset(m.protocol, o.data, o.split_file, g);
  o.eval.impute = o.flags.Apply(m.impute);
  o.eval.forecaster = LoadHistoryForecaster(o.forecaster, o.eval.k, o.eval.seed, model.threads());
  StageBars bars(!g.quiet);
  o.eval.progress = bars.Callback();
  const HgvaeEvaluation e = EvaluateHgvae(model, ds, o.eval);
  bars.Finish();
  PrintText(HgvaeEvaluationText(e, model, o.model, o.eval.impute));
  EmitJson(o.json_out, HgvaeEvaluationJson(e, model, o.model, o.eval.impute));
}

}  // namespace

void AddImputeCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<ImputeCmd>(
      &app, global, RunImpute, "impute",
      R"(Fill the missing values of a motion with an HG-VAE: NaN values in .npy, empty or nan fields in
.csv, and/or --mask. A bundle with a refiner (models/bandai/hgvae) corrects their spline fill;
otherwise they start at the training mean and Adam moves them to raise the model's score, each
window keeping its best step (--steps: after the refiner too). Observed values are kept exactly.)");
  AddModelOption(cmd, &o->model,
                 "HG-VAE bundle folder (hgvae.yaml + hgvae.pt), e.g. models/bandai/hgvae");
  AddMotionArgument(cmd, &o->motion, "Motion file (.npy, .csv, .bvh)", "--motion");
  cmd->add_option(
      "--mask", o->masks,
      "Values to treat as missing, repeatable: random:SHARE (e.g. random:0.1), joints:A,B (every "
      "frame), joints:A,B@FIRST-LAST (0-based frames), or MASK.npy ([T, J] or [T, J, 3], non-zero: "
      "missing)");
  cmd->add_option("--class", o->cls, "Condition on this class (conditional models; default none)");
  cmd->add_option("--seed", o->seed, "Seed of random masks (default 0)")->check(Seed);
  AddImputeOverrides(cmd, &o->flags);
  AddOutOption(cmd, &o->out, "Output motion file (.npy, .csv or .bvh)");
  AddMotionInputOptions(cmd, &o->input);
}

void AddOodCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<OodCmd>(
      &app, global, RunOod, "ood",
      R"(Score a motion's windows with an HG-VAE and flag those out of distribution: posterior score
below the training windows' mean - k std (k in the bundle). Exit status 1 when any window is flagged.)");
  AddModelOption(cmd, &o->model, "HG-VAE bundle folder");
  AddMotionArgument(cmd, &o->motion, "Motion file (.npy, .csv, .bvh)", "--motion");
  cmd->add_option("--stride", o->stride,
                  "Frames between window starts (default: the window length)")
      ->check(PositiveNumber);
  cmd->add_option("--class", o->cls, "Condition on this class (conditional models; default none)");
  AddJsonOption(cmd, &o->json_out, "The scores");
  AddMotionInputOptions(cmd, &o->input);
}

void AddHgvaeSampleCommand(CLI::App& hgvae, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<SampleCmd>(&hgvae, global, RunSample, "sample",
                                                 "Sample motion windows from an HG-VAE's prior, "
                                                 "optionally of one class (conditional models).");
  AddModelOption(cmd, &o->model, "HG-VAE bundle folder");
  cmd->add_option("--class", o->cls, "Class to sample (e.g. walk); default none (unconditional)");
  cmd->add_option("-n,--count", o->count,
                  "Windows to sample (default 1); written one after another")
      ->check(PositiveNumber);
  cmd->add_option("--seed", o->seed, "Random seed (default 0)")->check(Seed);
  cmd->add_flag("--mean-latents", o->mean_latents, "Each level's prior mean instead of a sample");
  AddOutOption(cmd, &o->out, "Output motion file (.npy, .csv or .bvh)");
}

void AddHgvaeEvalCommand(CLI::App& hgvae, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<EvalCmd>(
      &hgvae, global, RunEval, "eval",
      R"(An HG-VAE's figures on its protocol's test split: likelihood (ELBO, KL per level), imputation
of windows vs mean imputation, of whole clips vs interpolation and rigid limbs (random values, gaps
of 1 frame to 2 s, whole clips), out-of-distribution AUROC, and with --forecaster the forecasting
ADE/FDE from clean, mean-imputed and imputed histories.)");
  AddModelOption(cmd, &o->model, "HG-VAE bundle folder");
  AddDataOptions(cmd, &o->data, &o->split_file, "Data folder of the model's protocol");
  cmd->add_option("--windows", o->eval.windows, "Test windows, spread evenly (default 1000)")
      ->check(PositiveNumber);
  cmd->add_option("--gap-clips", o->eval.gap_clips, "Whole test clips (default 40; 0: none)")
      ->check(NonNegativeNumber);
  AddForecasterOptions(cmd, &o->forecaster, &o->eval.forecast_windows, &o->eval.k,
                       "Protocol test windows for them (default 500)");
  cmd->add_option("--forecast-occlusion", o->eval.forecast_occlusions,
                  "Only this forecasting row, repeatable (e.g. 'random 50%'; default: all)");
  cmd->add_option("--seed", o->eval.seed, "Seed of masks and samples (default 0)")->check(Seed);
  cmd->add_option("--slow", o->eval.slow,
                  "Play the test clips this many times slower first (default 1)")
      ->check(PositiveNumber);
  cmd->add_flag("--likelihood-only", o->eval.likelihood_only, "Only the likelihood figures");
  AddThreadsOption(cmd, &o->threads);
  AddImputeOverrides(cmd, &o->flags);
  AddJsonOption(cmd, &o->json_out, "Every figure");
}

}  // namespace motionfork::app
