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
  std::string out, format = "npy";
};

void RunPredict(PredictOptions o, const GlobalOptions& g) {
  RequireMotion(o.histories.empty() ? "" : o.histories[0]);
  o.files.input.config_dir = ConfigDir(g.config_dir);
  o.files.request.repair = !o.no_repair;
  o.files.bvh = o.format == "bvh";
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
(skeleton, parts, and per sample: whether it is valid and which test it fails -- angle ranges,
prior NLL above its bound, a doubted history -- and the mean prior NLL of its future). The
history is checked first (size, axes, left/right, bones, the model's own scores): a doubt is a
warning, and with --strict an error (exit 2). --format bvh also writes the samples as BVH on
the history's own rig.
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
  cmd->add_option("--format", o->format,
                  "npy: OUT.npy and OUT.json (default); bvh: also every sample as OUT_00.bvh ... "
                  "on the history's own BVH rig (its joints, unit, axes, rate), as 'motionfork "
                  "export' writes them")
      ->check(CLI::IsMember({"npy", "bvh"}));
  AddThreadsOption(cmd, &o->threads);
  AddPrecisionOption(cmd, &o->files.precision);
  AddMotionInputOptions(cmd, &o->files.input);
}

}  // namespace motionfork::app
