// motionfork predict: K futures of a history with a trained model bundle (pipeline/predict.h).
#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "motion_options.h"
#include "pipeline/predict_to_files.h"
#include "torch_util/threads.h"

namespace motionfork::app {
namespace {

struct PredictOptions {
  pipeline::PredictFiles files;
  std::vector<std::string> histories;
  bool no_repair = false;
  int threads = 0;
  std::string out;
};

void RunPredict(PredictOptions o, const GlobalOptions& g) {
  RequireMotion(o.histories.empty() ? "" : o.histories[0]);
  o.files.input.config_dir = ConfigDir(g.config_dir);
  o.files.request.repair = !o.no_repair;
  ProgressBar bar("predicting", o.histories.size() > 1 && !g.quiet);
  const std::string report =
      pipeline::PredictToFiles(o.files, o.histories, o.out, WindowThreads(o.threads),
                               [&bar](double done) { bar.Update(done); });
  bar.Finish();
  PrintText(report);
}

}  // namespace

void AddPredictCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] =
      AddSubcommand<PredictOptions>(&app, global, RunPredict, "predict",
                                    R"(Predict K futures of a history with a trained model bundle.
Writes OUT.npy [K, t_his + t_pred, J, 3] (each sample: the history, then its future; metres;
the root stays where the history ended: models predict root-relative poses) and OUT.json
(skeleton, parts, and per sample: angle-range validity and mean prior NLL of its future).
Several files: OUT/NAME.npy and OUT/NAME.json each, as predicted alone, shared by --threads.)");
  AddModelOption(cmd, &o->files.model_dir, "Model bundle folder (model.yaml + generator.pt)");
  AddMotionArgument(
      cmd, &o->histories,
      "Motion file(s) holding the history (.bvh, .npy, .csv); several: OUT is a folder",
      "--history");
  cmd->add_option("--start", o->files.start,
                  "First history frame (default: the last t_his frames of the file)")
      ->check(NonNegativeNumber);
  cmd->add_option("-k", o->files.request.k, "Futures to predict (default 50, at most 10000)")
      ->check(PositiveNumber);
  cmd->add_option("--fix", o->files.request.fixed_parts,
                  "Body part whose latent all K futures share (e.g. legs: same legs, varied upper "
                  "body); repeat for several");
  cmd->add_option("--seed", o->files.request.seed,
                  "Random seed: the same seed gives the same futures (default 0)")
      ->check(Seed);
  cmd->add_flag("--no-repair", o->no_repair,
                "Keep the network's raw futures: by default poses that break the bundle's angle "
                "ranges (constraints.yaml) are moved back inside them, as little as it takes");
  cmd->add_option(
      "--impute", o->files.imputer_dir,
      "HG-VAE bundle (e.g. models/bandai/hgvae) filling the history's missing values: NaN in .npy, "
      "empty or nan fields in .csv, and --mask");
  cmd->add_option(
      "--mask", o->files.masks,
      "With --impute: values to treat as missing, repeatable: random:SHARE, joints:A,B or "
      "joints:A,B@FIRST-LAST");
  cmd->add_option("--denoise", o->files.denoiser_dir,
                  "Motion-DVAE bundle (e.g. models/bandai/dvae) denoising the history first (after "
                  "--impute), with\n"
                  "up to one model window of earlier frames as context");
  AddOutOption(cmd, &o->out,
               "Output path (OUT.npy and OUT.json are written; a folder for several files)");
  AddThreadsOption(cmd, &o->threads);
  AddMotionInputOptions(cmd, &o->files.input);
}

}  // namespace motionfork::app
