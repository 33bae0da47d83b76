// motionfork dvae: the Motion-DVAE motion prior and its unsupervised denoising training:
// `dvae train` (clean windows) and `dvae finetune` (noisy windows, regression mode).
#include <cstdio>
#include <memory>

#include "app_common.h"
#include "bundle/dvae_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset_loading.h"
#include "denoise/training/dvae_training.h"
#include "dvae_commands.h"

namespace motionfork::app {
namespace {

struct DvaeTrainCmd {
  std::string config = "dvae_bandai";
  std::string data, out, prior, split_file;
  int epochs = 0, stop_after = 0;
};

struct Loaded {
  DvaeTrainConfig config;
  ProtocolOptions protocol;
  SkeletonConfig skeleton;
  DvaeData data;
};

Loaded LoadForTraining(const DvaeTrainCmd& o, const GlobalOptions& g, bool finetune) {
  const std::string config_dir = ConfigDir(g.config_dir);
  Loaded l;
  l.config = LoadDvaeTrainConfig(ResolveConfigPath(config_dir, "models", o.config));
  if (o.epochs > 0) (finetune ? l.config.finetune.epochs : l.config.training.epochs) = o.epochs;
  l.protocol = LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", l.config.protocol));
  l.skeleton = LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", l.protocol.skeleton));
  const Dataset ds = LoadDatasetWithProgress(l.protocol, l.skeleton, o.data, o.split_file, g);
  l.data = MakeDvaeData(ds, l.config.training.held_out_share, l.config.training.seed,
                        l.config.model.window);
  size_t frames = 0;
  for (const auto& c : l.data.train) frames += c.size() / (3 * l.data.joints);
  std::printf(
      "Motion-DVAE: windows of %d frames x %d joints; %zu training clips (%s frames), %zu held "
      "out\n",
      l.config.model.window, l.data.joints, l.data.train.size(), WithThousands(frames).c_str(),
      l.data.held_out.size());
  return l;
}

DvaeTrainCallbacks Callbacks(int epochs, const GlobalOptions& g,
                             std::unique_ptr<ProgressBar>* bar) {
  DvaeTrainCallbacks cb;
  cb.step = [bar, epochs, &g](int epoch, double fraction, double loss) {
    if (!*bar)
      *bar = std::make_unique<ProgressBar>(
          "epoch " + std::to_string(epoch + 1) + "/" + std::to_string(epochs), !g.quiet);
    char detail[64];
    std::snprintf(detail, sizeof(detail), "loss %.5g", loss);
    (*bar)->Update(fraction, detail);
  };
  cb.epoch = [bar, epochs](const DvaeEpochLog& log) {
    bar->reset();
    std::printf("epoch %d/%d (%s, kl weight %.3g):", log.epoch + 1, epochs,
                Duration(log.seconds).c_str(), log.kl_weight);
    for (const auto& [name, v] : log.terms) std::printf(" %s %.5g", name.c_str(), v);
    std::printf("\n");
    std::fflush(stdout);
  };
  cb.message = [](const std::string& m) { std::printf("%s\n", m.c_str()); };
  return cb;
}

void RunTrain(const DvaeTrainCmd& o, const GlobalOptions& g) {
  const Loaded l = LoadForTraining(o, g, false);
  DvaeManifest base;
  base.protocol = l.protocol.name;
  base.fps = l.protocol.fps;
  base.skeleton = l.skeleton.skeleton->ToSpec();
  base.noise_prior = l.config.noise_prior;
  base.denoise = l.config.denoise;
  base.info = {{"config", l.config.name},
               {"seed", std::to_string(l.config.training.seed)},
               {"epochs", std::to_string(l.config.training.epochs)}};
  std::unique_ptr<ProgressBar> bar;
  const DvaeTrainSummary s = TrainDvae(l.config, base, l.data, o.out,
                                       Callbacks(l.config.training.epochs, g, &bar), o.stop_after);
  std::printf(
      "trained epochs %d..%d in %s; motion prior bundle: %s (dvae.yaml, dvae.pt), log: %s/log.csv\n"
      "next: motionfork dvae finetune --prior %s --data DIR --out DIR\n",
      s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(), o.out.c_str(), o.out.c_str(),
      o.out.c_str());
}

void RunFinetune(const DvaeTrainCmd& o, const GlobalOptions& g) {
  const Loaded l = LoadForTraining(o, g, true);
  std::printf("unsupervised denoising training on noisy windows:");
  for (const std::string& n : l.config.finetune.noise) std::printf(" %s", n.c_str());
  std::printf(
      " (the encoder, initial-state and noise predictors learn; decoder and prior stay fixed)\n");
  std::unique_ptr<ProgressBar> bar;
  const DvaeTrainSummary s = FinetuneDvae(
      l.config, o.prior, l.data, o.out, Callbacks(l.config.finetune.epochs, g, &bar), o.stop_after);
  std::printf(
      "fine-tuned epochs %d..%d in %s%s; denoiser bundle: %s (the epoch with the lowest held-out "
      "loss), log: %s/log.csv\n",
      s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(),
      s.stopped_early ? " (stopped early: the held-out loss stopped improving)" : "", o.out.c_str(),
      o.out.c_str());
}

void AddCommonOptions(CLI::App* cmd, DvaeTrainCmd* t) {
  cmd->add_option("--config", t->config,
                  "Config name (configs/models/) or YAML path (default dvae_bandai)");
  cmd->add_option("--data", t->data, "Data folder of the config's protocol")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", t->out, "Output folder (bundle, log.csv, checkpoint/)")->required();
  cmd->add_option("--split", t->split_file, "Split file overriding the protocol's");
  cmd->add_option("--epochs", t->epochs, "Override the config's epoch count")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--stop-after", t->stop_after,
                  "Stop after this many epochs of this run (resume later)")
      ->check(CLI::PositiveNumber);
}

}  // namespace

void AddDvaeCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* dv = app.add_subcommand(
      "dvae",
      "Motion-DVAE: a dynamical VAE motion prior (LSTM over per-frame latents) and its "
      "unsupervised\n"
      "denoising training. Use the result with 'motionfork denoise' or 'predict --denoise'.");
  dv->require_subcommand(1);
  auto t = std::make_shared<DvaeTrainCmd>();
  CLI::App* train = dv->add_subcommand("train",
                                       "Train the motion prior (configs/models/NAME.yaml, 'model' "
                                       "and 'training') on clean windows of a\n"
                                       "protocol's training split. Every epoch writes the bundle, "
                                       "a row of OUT/log.csv and a checkpoint;\n"
                                       "running the same command again resumes.");
  AddCommonOptions(train, t.get());
  train->callback([t, &global] { RunTrain(*t, global); });
  auto f = std::make_shared<DvaeTrainCmd>();
  CLI::App* finetune = dv->add_subcommand("finetune",
                                          "Unsupervised denoising training ('regression mode', the "
                                          "config's 'finetune'): windows of the\n"
                                          "training split corrupted by the config's noise kinds, "
                                          "no clean targets; the encoder, initial-state\n"
                                          "and noise predictors learn, the prior stays fixed. "
                                          "Early stopping on a held-out loss; resumable.");
  AddCommonOptions(finetune, f.get());
  finetune->add_option("--prior", f->prior, "Motion prior bundle from 'dvae train'")
      ->required()
      ->check(CLI::ExistingDirectory);
  finetune->callback([f, &global] { RunFinetune(*f, global); });
  AddDvaeEvalCommand(*dv, global);
}

}  // namespace motionfork::app
