// motionfork hgvae: the HG-VAE motion-window model: train, sample, evaluate.
#include <cstdio>

#include "app_common.h"
#include "bundle/hgvae_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "experiment_common.h"
#include "flags.h"
#include "imputation/training/hgvae_training.h"
#include "imputation/training/hgvae_training_text.h"

namespace motionfork::app {
namespace {

struct HgvaeTrainCmd {
  std::string config = "hgvae_bandai";
  TrainingRunFlags run;
};

HgvaeTrainCallbacks EpochReports(EpochBars* bars) {
  HgvaeTrainCallbacks cb;
  cb.step = [bars](int epoch, double fraction, double loss, double nll, double kl) {
    char detail[96];
    std::snprintf(detail, sizeof(detail), "loss %.4g nll %.4g kl %.4g", loss, nll, kl);
    bars->Update(epoch, fraction, detail);
  };
  cb.epoch = [bars](const HgvaeEpochLog& log) {
    bars->PrintEpoch(log.epoch, log.seconds, log.terms, 5, log.kl_weight);
  };
  cb.message = PrintMessage;
  return cb;
}

void RunHgvaeTrain(const HgvaeTrainCmd& o, GlobalOptions& g) {
  const TrainingRunFlags& run = o.run;
  if (LaunchIfRequested(run.launch, g)) return;
  HgvaeTrainConfig cfg =
      LoadHgvaeTrainConfig(ResolveConfigPath(ConfigDir(g.config_dir), "models", o.config));
  if (run.epochs > 0) cfg.training.epochs = run.epochs;
  const Dataset ds = LoadProtocolDataset(cfg.protocol, run.data, run.split_file, g);
  const ProtocolOptions& protocol = ds.protocol;
  const int coords = 3 * (ds.skeleton.skeleton->num_joints() - 1);
  const HgvaeManifest base = HgvaeTrainingManifest(cfg, protocol, *ds.skeleton.skeleton);
  cfg.model = ResolveHgvaeOptions(cfg.model, coords, protocol.t_his);
  const HgvaeData data = MakeHgvaeData(ds, cfg.training, cfg.model.window);
  PrintText(HgvaeDataText(data, cfg.model.window));
  EpochBars bars(cfg.training.epochs, !g.quiet);
  const HgvaeTrainSummary s =
      TrainHgvae(cfg, base, data, run.out, EpochReports(&bars), run.stop_after);
  if (s.first_epoch >= cfg.training.epochs && IsRankZero())
    RefreshBundleSettings(run.out, data, cfg);
  PrintText(HgvaeTrainingDoneText(s, cfg, run.out));
}

}  // namespace

void AddHgvaeCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* hg = app.add_subcommand(
      "hgvae",
      "HG-VAE: a hierarchical graph-convolutional VAE of motion windows (imputation of missing\n"
      "values, out-of-distribution scores, sampling). See also 'motionfork impute' and 'motionfork "
      "ood'.");
  hg->require_subcommand(1);
  const auto [train, t] = AddSubcommand<HgvaeTrainCmd>(
      hg, global, RunHgvaeTrain, "train",
      R"(Train an HG-VAE (configs/models/NAME.yaml) on a protocol's training split. Every epoch writes
the bundle (OUT/hgvae.yaml, OUT/hgvae.pt), a row of OUT/log.csv and a checkpoint; running the
same command again resumes where it stopped.)");
  train->add_option("--config", t->config,
                    "Config name (configs/models/) or YAML path (default hgvae_bandai)");
  AddTrainingRunOptions(train, &t->run, "Output folder (bundle, log, checkpoint)");
  AddHgvaeSampleCommand(*hg, global);
  AddHgvaeEvalCommand(*hg, global);
}

}  // namespace motionfork::app
