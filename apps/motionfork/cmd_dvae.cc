// motionfork dvae: the Motion-DVAE motion prior and its unsupervised denoising training:
// `dvae train` (clean windows) and `dvae finetune` (noisy windows, regression mode).
#include <cstdio>

#include "app_common.h"
#include "bundle/dvae_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "denoise/training/dvae_training.h"
#include "experiment_common.h"
#include "flags.h"

namespace motionfork::app {
namespace {

struct DvaeTrainCmd {
  std::string config = "dvae_bandai";
  std::string prior;
  TrainingRunFlags run;
};

struct Loaded {
  DvaeTrainConfig config;
  ProtocolOptions protocol;
  SkeletonConfig skeleton;
  DvaeData data;
};

Loaded LoadForTraining(const DvaeTrainCmd& o, const GlobalOptions& g, bool finetune) {
  const TrainingRunFlags& run = o.run;
  Loaded l;
  l.config = LoadDvaeTrainConfig(ResolveConfigPath(ConfigDir(g.config_dir), "models", o.config));
  if (run.epochs > 0) (finetune ? l.config.finetune.epochs : l.config.training.epochs) = run.epochs;
  const Dataset ds = LoadProtocolDataset(l.config.protocol, run.data, run.split_file, g);
  l.protocol = ds.protocol;
  l.skeleton = ds.skeleton;
  l.data = MakeDvaeData(ds, l.config.training.held_out_share, l.config.training.seed,
                        l.config.model.window);
  std::printf(
      "Motion-DVAE: windows of %d frames x %d joints; %zu training clips (%s frames), %zu held "
      "out\n",
      l.config.model.window, l.data.joints, l.data.train.size(),
      WithThousands(l.data.train_frames()).c_str(), l.data.held_out.size());
  return l;
}

DvaeTrainCallbacks EpochReports(EpochBars* bars) {
  DvaeTrainCallbacks cb;
  cb.step = [bars](int epoch, double fraction, double loss) {
    char detail[64];
    std::snprintf(detail, sizeof(detail), "loss %.5g", loss);
    bars->Update(epoch, fraction, detail);
  };
  cb.epoch = [bars](const DvaeEpochLog& log) {
    bars->PrintEpoch(log.epoch, log.seconds, log.terms, 5, log.kl_weight);
  };
  cb.message = PrintMessage;
  return cb;
}

void RunTrain(const DvaeTrainCmd& o, GlobalOptions& g) {
  const std::string& out = o.run.out;
  if (LaunchIfRequested(o.run.launch, g)) return;
  const Loaded l = LoadForTraining(o, g, false);
  const DvaeManifest base = DvaeTrainingManifest(l.config, l.protocol, *l.skeleton.skeleton);
  EpochBars bars(l.config.training.epochs, !g.quiet);
  const DvaeTrainSummary s =
      TrainDvae(l.config, base, l.data, out, EpochReports(&bars), o.run.stop_after);
  std::printf(
      "trained epochs %d..%d in %s; motion prior bundle: %s (dvae.yaml, dvae.pt), log: %s/log.csv\n"
      "next: motionfork dvae finetune --prior %s --data DIR --out DIR\n",
      s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(), out.c_str(), out.c_str(),
      out.c_str());
}

void RunFinetune(const DvaeTrainCmd& o, GlobalOptions& g) {
  const std::string& out = o.run.out;
  if (LaunchIfRequested(o.run.launch, g)) return;
  const Loaded l = LoadForTraining(o, g, true);
  std::printf("unsupervised denoising training on noisy windows:");
  for (const std::string& n : l.config.finetune.noise) std::printf(" %s", n.c_str());
  std::printf(
      " (the encoder, initial-state and noise predictors learn; decoder and prior stay fixed)\n");
  EpochBars bars(l.config.finetune.epochs, !g.quiet);
  const DvaeTrainSummary s =
      FinetuneDvae(l.config, o.prior, l.data, out, EpochReports(&bars), o.run.stop_after);
  std::printf(
      "fine-tuned epochs %d..%d in %s%s; denoiser bundle: %s (the epoch with the lowest held-out "
      "loss), log: %s/log.csv\n",
      s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(),
      s.stopped_early ? " (stopped early: the held-out loss stopped improving)" : "", out.c_str(),
      out.c_str());
}

void AddCommonOptions(CLI::App* cmd, DvaeTrainCmd* t) {
  cmd->add_option("--config", t->config,
                  "Config name (configs/models/) or YAML path (default dvae_bandai)");
  AddTrainingRunOptions(cmd, &t->run, "Output folder (bundle, log.csv, checkpoint/)");
}

}  // namespace

void AddDvaeCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* dv = app.add_subcommand(
      "dvae",
      "Motion-DVAE: a dynamical VAE motion prior (LSTM over per-frame latents) and its "
      "unsupervised\n"
      "denoising training. Use the result with 'motionfork denoise' or 'predict --denoise'.");
  dv->require_subcommand(1);
  const auto [train, t] = AddSubcommand<DvaeTrainCmd>(
      dv, global, RunTrain, "train",
      R"(Train the motion prior (configs/models/NAME.yaml, 'model' and 'training') on clean windows of a
protocol's training split. Every epoch writes the bundle, a row of OUT/log.csv and a checkpoint;
running the same command again resumes.)");
  AddCommonOptions(train, t.get());
  const auto [finetune, f] = AddSubcommand<DvaeTrainCmd>(
      dv, global, RunFinetune, "finetune",
      R"(Unsupervised denoising training ('regression mode', the config's 'finetune'): windows of the
training split corrupted by the config's noise kinds, no clean targets; the encoder, initial-state
and noise predictors learn, the prior stays fixed. Early stopping on a held-out loss; resumable.)");
  AddCommonOptions(finetune, f.get());
  finetune->add_option("--prior", f->prior, "Motion prior bundle from 'dvae train'")
      ->required()
      ->check(CLI::ExistingDirectory);
  AddDvaeEvalCommand(*dv, global);
}

}  // namespace motionfork::app
