// motionfork dvae: the Motion-DVAE motion prior and its denoising training: `dvae train` (clean
// windows), `dvae finetune` (noisy windows, regression mode) and `dvae refine` (the refiner).
#include <cstdio>

#include "app_common.h"
#include "bundle/dvae_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "denoise/training/dvae_training.h"
#include "denoise/training/dvae_training_text.h"
#include "experiment_common.h"
#include "flags.h"

namespace motionfork::app {
namespace {

struct DvaeTrainCmd {
  std::string config = "dvae_bandai";
  std::string prior;
  TrainingRunFlags run;
  bool blend_only = false;  // refine: the prior's refiner kept, its blend fitted again
};

void RunStage(DvaeStage stage, const DvaeTrainCmd& o, GlobalOptions& g) {
  const TrainingRunFlags& run = o.run;
  if (LaunchIfRequested(run.launch, g)) return;
  DvaeTrainConfig c =
      LoadDvaeTrainConfig(ResolveConfigPath(ConfigDir(g.config_dir), "models", o.config));
  int& epochs = stage == DvaeStage::kPrior      ? c.training.epochs
                : stage == DvaeStage::kFinetune ? c.finetune.epochs
                                                : c.refiner.training.epochs;
  if (run.epochs > 0) epochs = run.epochs;
  const Dataset ds = LoadProtocolDataset(c.protocol, run.data, run.split_file, g);
  const DvaeData data =
      MakeDvaeData(ds, c.training.held_out_share, c.training.seed, c.model.window);
  PrintText(DvaeTrainingStartText(stage, c, data));
  EpochBars bars(epochs, !g.quiet);
  const auto cb = LossEpochReports<DvaeTrainCallbacks>(&bars);
  const DvaeTrainSummary s =
      stage == DvaeStage::kPrior
          ? TrainDvae(c, DvaeTrainingManifest(c, ds.protocol, *ds.skeleton.skeleton), data, run.out,
                      cb, run.stop_after)
      : stage == DvaeStage::kFinetune ? FinetuneDvae(c, o.prior, data, run.out, cb, run.stop_after)
      : o.blend_only                  ? RefitRefinerBlend(c, o.prior, data, run.out)
                                      : RefineDvae(c, o.prior, data, run.out, cb, run.stop_after);
  PrintText(DvaeTrainingDoneText(stage, s, run.out));
}

void AddStage(CLI::App* dv, GlobalOptions& global, DvaeStage stage, const char* name,
              const char* description, const char* prior) {
  const auto [cmd, t] = AddSubcommand<DvaeTrainCmd>(
      dv, global, [stage](const DvaeTrainCmd& o, GlobalOptions& g) { RunStage(stage, o, g); }, name,
      description);
  cmd->add_option("--config", t->config,
                  "Config name (configs/models/) or YAML path (default dvae_bandai)");
  AddTrainingRunOptions(cmd, &t->run, "Output folder (bundle, log.csv, checkpoint/)");
  if (prior) cmd->add_option("--prior", t->prior, prior)->required()->check(CLI::ExistingDirectory);
  if (stage == DvaeStage::kRefiner) {
    cmd->add_flag("--blend-only", t->blend_only,
                  "Keep --prior's refiner as it is: fit only its blend and outlier repair again");
  }
}

}  // namespace

void AddDvaeCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* dv = app.add_subcommand(
      "dvae",
      "Motion-DVAE: a dynamical VAE motion prior (LSTM over per-frame latents), its unsupervised\n"
      "denoising training and its refiner. Use the result with 'motionfork denoise' or 'predict "
      "--denoise'.");
  dv->require_subcommand(1);
  AddStage(
      dv, global, DvaeStage::kPrior, "train",
      R"(Train the motion prior (configs/models/NAME.yaml, 'model' and 'training') on clean windows of a
protocol's training split. Every epoch writes the bundle, a row of OUT/log.csv and a checkpoint;
running the same command again resumes.)",
      nullptr);
  AddStage(
      dv, global, DvaeStage::kFinetune, "finetune",
      R"(Unsupervised denoising training ('regression mode', the config's 'finetune'): windows of the
training split corrupted by the config's noise kinds, no clean targets; the encoder, initial-state
and noise predictors learn, the prior stays fixed. Early stopping on a held-out loss; resumable.)",
      "Motion prior bundle from 'dvae train'");
  AddStage(
      dv, global, DvaeStage::kRefiner, "refine",
      R"(Train the denoising refiner of a bundle (the config's 'refiner'): a temporal convolution
network learns, on clean training windows corrupted at random levels, to give the clean window
back. OUT: the bundle with its refiner (denoise mode 'refiner'). Early stopping; resumable.)",
      "Motion-DVAE bundle to add the refiner to (e.g. 'dvae finetune''s)");
  AddDvaeEvalCommand(*dv, global);
}

}  // namespace motionfork::app
