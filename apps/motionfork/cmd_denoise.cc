// motionfork denoise / dvae eval: using a trained Motion-DVAE denoiser.
#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "bundle/dvae_bundle.h"
#include "commands.h"
#include "denoise/dvae_model.h"
#include "denoise/training/dvae_evaluation.h"
#include "denoise/training/dvae_evaluation_json.h"
#include "denoise/training/dvae_evaluation_text.h"
#include "experiment_common.h"
#include "flags.h"
#include "generator/training/history_forecaster.h"
#include "io/motion_file.h"
#include "motion_options.h"
#include "pipeline/denoise_file.h"
#include "torch_util/threads.h"

namespace motionfork::app {
namespace {

void AddDenoiseOverrides(CLI::App* cmd, DenoiseOverrides* f) {
  cmd->add_option("--mode", f->mode,
                  "refiner (the bundle's supervised refiner), regression (one pass of the "
                  "fine-tuned encoder) or\noptimisation (Adam steps on the sequence's own loss "
                  "first); default: the bundle's")
      ->check(CLI::IsMember({"refiner", "regression", "optimisation", "optimization"}));
  cmd->add_option("--iterations", f->iterations,
                  "Optimisation mode: Adam steps (default: the bundle's, 50)")
      ->check(NonNegativeNumber);
  cmd->add_option("--draws", f->samples,
                  "Posterior draws averaged; 0 = posterior means (default: the bundle's)")
      ->check(NonNegativeNumber);
  AddDeprecatedOption(cmd, "--samples", "--draws", &f->samples);
  cmd->add_option("--seed", f->seed, "Seed of the posterior draws (default: the bundle's)")
      ->check(Seed);
  cmd->add_option("--blend", f->blend,
                  "fused (the paper's: decoder and input weighted by their variances) or decoder "
                  "(the decoder's\n"
                  "frames alone, smoother); default: the bundle's")
      ->check(CLI::IsMember({"fused", "decoder"}));
  AddDeprecatedOption(cmd, "--output", "--blend", &f->blend);
}

// ---- denoise ----
struct DenoiseCmd {
  std::string model, motion, out, noise;
  uint64_t noise_seed = 0;
  int threads = 0;
  DenoiseOverrides flags;
  MotionInputOptions input;
};

void RunDenoise(const DenoiseCmd& o, const GlobalOptions& g) {
  RequireMotion(o.motion);
  DvaeModel model = LoadDvaeModel(o.model);
  model.set_threads(WindowThreads(o.threads));
  const MotionWithGaps in = LoadMotionForModel(o.motion, o.input, g, model.skeleton(),
                                               model.manifest().fps, model.manifest().protocol);
  pipeline::RequireComplete(o.motion, in.missing,
                            "fill them first ('motionfork impute'), then denoise");
  const DenoiseOptions options = o.flags.Apply(model.manifest().denoise);
  ProgressBar bar(std::string("denoising (") + ToString(options.mode) + ")", !g.quiet);
  const pipeline::DenoisedFile d =
      pipeline::DenoiseFile(model, o.motion, in.motion, o.noise, o.noise_seed, options,
                            [&bar](double f) { bar.Update(f); });
  bar.Finish();
  WriteMotionFile(o.out, d.denoised);
  PrintText(pipeline::DenoisedFileText(model, d, o.out));
}

// ---- dvae eval ----
struct EvalCmd {
  std::string model, data, split_file, forecaster, json_out;
  int threads = 0;
  DvaeEvalOptions eval;
  DenoiseOverrides flags;
};

// The header once the clips are chosen, then each noise kind's row as it is measured.
void PrintProgress(const EvalCmd& o, const DvaeModel& model, const DvaeEvaluation& e) {
  PrintText(e.settings.empty() ? DvaeEvaluationHeaderText(e, model, o.model).c_str()
                               : DenoisingRowText(e.settings.back()));
  std::fflush(stdout);
}

void RunEval(EvalCmd o, const GlobalOptions& g) {
  DvaeModel model = LoadDvaeModel(o.model);
  model.set_threads(WindowThreads(o.threads));
  const Dataset ds = LoadProtocolDataset(model.manifest().protocol, o.data, o.split_file, g);
  o.eval.denoise = o.flags.Apply(model.manifest().denoise);
  o.eval.forecaster = LoadHistoryForecaster(o.forecaster, o.eval.k, o.eval.seed, model.threads());
  ProgressBar bar("noise settings", !g.quiet);
  const DvaeEvaluation e = EvaluateDvae(model, ds, o.eval, [&](const DvaeEvaluation& partial) {
    PrintProgress(o, model, partial);
    bar.Update(double(partial.settings.size()) / o.eval.noises.size());
  });
  bar.Finish();
  PrintText(DvaeEvaluationFooterText(e, model.threads()));
  EmitJson(o.json_out, DvaeEvaluationJson(e, o.model));
}

}  // namespace

void AddDenoiseCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, d] = AddSubcommand<DenoiseCmd>(
      &app, global, RunDenoise, "denoise",
      R"(Denoise a motion file (estimated, noisy joint positions) with a Motion-DVAE bundle, e.g.
models/bandai/dvae. Windows of the model's length every 'stride' frames, blended.)");
  AddModelOption(cmd, &d->model, "Motion-DVAE bundle folder")->check(CLI::ExistingDirectory);
  AddMotionArgument(cmd, &d->motion, "Motion file (.npy, .csv, .bvh, .npz)", "--motion");
  AddOutOption(cmd, &d->out, "Output motion file (format from the extension)");
  cmd->add_option(
      "--add-noise", d->noise,
      "Corrupt the input first (a test): gaussian:S, outliers:P,S or jitter:S (metres)");
  cmd->add_option("--noise-seed", d->noise_seed, "Seed of --add-noise (default 0)")->check(Seed);
  AddThreadsOption(cmd, &d->threads);
  AddDenoiseOverrides(cmd, &d->flags);
  AddMotionInputOptions(cmd, &d->input);
}

void AddDvaeEvalCommand(CLI::App& dvae, GlobalOptions& global) {
  const auto [cmd, e] = AddSubcommand<EvalCmd>(
      &dvae, global, RunEval, "eval",
      R"(Denoising figures on a protocol's test split: error of noisy, filtered (Gaussian, Savitzky-Golay,
one-euro; each tuned on training clips), denoised (regression mode) and optimised (optimisation
mode) motion against the clean one per noise kind, acceleration against the clean motion's, speed,
and with --forecaster the forecasting ADE/FDE from noisy and denoised histories.)");
  AddModelOption(cmd, &e->model, "Motion-DVAE bundle folder")->check(CLI::ExistingDirectory);
  AddDataOptions(cmd, &e->data, &e->split_file, "Data folder of the bundle's protocol");
  cmd->add_option(
      "--noise", e->eval.noises,
      "Noise kinds (repeatable; default: gaussian 2/5/10 cm, two outlier settings, jitter 5 cm)");
  cmd->add_option("--test-clips", e->eval.clips, "Test clips used, spread evenly (default 200)")
      ->check(PositiveNumber);
  AddDeprecatedOption(cmd, "--clips", "--test-clips", &e->eval.clips);
  cmd->add_option("--optimisation-clips", e->eval.optimisation_clips,
                  "Of those, how many optimisation mode runs on (default 20)")
      ->check(NonNegativeNumber);
  cmd->add_option("--tuning-clips", e->eval.tuning_clips,
                  "Training clips on which the baseline filters are tuned (default 50)")
      ->check(PositiveNumber);
  cmd->add_option("--slow", e->eval.slow,
                  "Play the test and tuning clips this many times slower first (default 1)")
      ->check(PositiveNumber);
  AddForecasterOptions(cmd, &e->forecaster, &e->eval.forecast_windows, &e->eval.k,
                       "Protocol test windows forecast (default 300)");
  AddThreadsOption(cmd, &e->threads);
  AddJsonOption(cmd, &e->json_out, "The figures");
  AddDenoiseOverrides(cmd, &e->flags);
}

}  // namespace motionfork::app
