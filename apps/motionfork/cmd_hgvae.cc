// motionfork hgvae: the HG-VAE motion-window model: train, sample, evaluate.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app_common.h"
#include "bundle/hgvae_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset_loading.h"
#include "hgvae_commands.h"
#include "imputation/training/hgvae_training.h"

namespace motionfork::app {
namespace {

struct HgvaeTrainCmd {
  std::string config = "hgvae_bandai";
  std::string data, out, split_file;
  int epochs = 0, stop_after = 0;
};

void RunHgvaeTrain(const HgvaeTrainCmd& o, const GlobalOptions& g) {
  const std::string config_dir = ConfigDir(g.config_dir);
  HgvaeTrainConfig cfg = LoadHgvaeTrainConfig(ResolveConfigPath(config_dir, "models", o.config));
  if (o.epochs > 0) cfg.training.epochs = o.epochs;
  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", cfg.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", protocol.skeleton));
  const Dataset ds = LoadDatasetWithProgress(protocol, skeleton, o.data, o.split_file, g);
  const int coords = 3 * (skeleton.skeleton->num_joints() - 1);
  HgvaeManifest base;
  base.protocol = protocol.name;
  base.fps = protocol.fps;
  base.skeleton = skeleton.skeleton->ToSpec();
  base.ood_k = cfg.ood_k;
  base.ood_score = cfg.ood_score;
  base.impute = cfg.impute;
  base.info = {{"config", cfg.name},
               {"seed", std::to_string(cfg.training.seed)},
               {"epochs", std::to_string(cfg.training.epochs)}};
  cfg.model = ResolveHgvaeOptions(cfg.model, coords, protocol.t_his);
  const HgvaeData data = MakeHgvaeData(ds, cfg.training, cfg.model.window);
  size_t train_frames = 0;
  for (const auto& p : data.train.poses) train_frames += p.size() / coords;
  std::printf(
      "HG-VAE: windows of %d frames x %d coordinates; %zu training clips (%s frames), %zu held "
      "out%s\n",
      cfg.model.window, coords, data.train.poses.size(), WithThousands(train_frames).c_str(),
      data.held_out.poses.size(),
      data.classes.empty()
          ? ""
          : (", " + std::to_string(data.classes.size()) + " action classes").c_str());
  HgvaeTrainCallbacks cb;
  std::unique_ptr<ProgressBar> bar;
  cb.step = [&](int epoch, double fraction, double loss, double nll, double kl) {
    if (!bar) {
      bar = std::make_unique<ProgressBar>(
          "epoch " + std::to_string(epoch + 1) + "/" + std::to_string(cfg.training.epochs),
          !g.quiet);
    }
    char detail[96];
    std::snprintf(detail, sizeof(detail), "loss %.4g nll %.4g kl %.4g", loss, nll, kl);
    bar->Update(fraction, detail);
  };
  cb.epoch = [&](const HgvaeEpochLog& log) {
    bar.reset();
    std::printf("epoch %d/%d (%s, kl weight %.3g):", log.epoch + 1, cfg.training.epochs,
                Duration(log.seconds).c_str(), log.kl_weight);
    for (const auto& [name, v] : log.terms) std::printf(" %s %.5g", name.c_str(), v);
    std::printf("\n");
    std::fflush(stdout);
  };
  cb.message = [](const std::string& m) { std::printf("%s\n", m.c_str()); };
  const HgvaeTrainSummary s = TrainHgvae(cfg, base, data, o.out, cb, o.stop_after);
  if (s.first_epoch >= cfg.training.epochs) {
    RefreshBundleSettings(o.out, data, cfg);
    std::printf(
        "all %d epochs were trained already; imputation defaults, OoD score and its statistics "
        "(%s) "
        "refreshed from the config; bundle: %s\n",
        cfg.training.epochs, ToString(cfg.ood_score), o.out.c_str());
    return;
  }
  std::printf("trained epochs %d..%d in %s; bundle: %s (hgvae.yaml, hgvae.pt), log: %s/log.csv\n",
              s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(), o.out.c_str(),
              o.out.c_str());
}

}  // namespace

void AddHgvaeCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* hg = app.add_subcommand(
      "hgvae",
      "HG-VAE: a hierarchical graph-convolutional VAE of motion windows (imputation of missing\n"
      "values, out-of-distribution scores, sampling). See also 'motionfork impute' and 'motionfork "
      "ood'.");
  hg->require_subcommand(1);
  auto t = std::make_shared<HgvaeTrainCmd>();
  CLI::App* train = hg->add_subcommand("train",
                                       "Train an HG-VAE (configs/models/NAME.yaml) on a protocol's "
                                       "training split. Every epoch writes\n"
                                       "the bundle (OUT/hgvae.yaml, OUT/hgvae.pt), a row of "
                                       "OUT/log.csv and a checkpoint; running the\n"
                                       "same command again resumes where it stopped.");
  train->add_option("--config", t->config,
                    "Config name (configs/models/) or YAML path (default hgvae_bandai)");
  train->add_option("--data", t->data, "Data folder of the config's protocol")
      ->required()
      ->check(CLI::ExistingDirectory);
  train->add_option("--out", t->out, "Output folder (bundle, log, checkpoint)")->required();
  train->add_option("--split", t->split_file, "Split file overriding the protocol's");
  train->add_option("--epochs", t->epochs, "Override the config's epoch count")
      ->check(CLI::PositiveNumber);
  train
      ->add_option("--stop-after", t->stop_after,
                   "Stop after this many epochs of this run (resume later)")
      ->check(CLI::PositiveNumber);
  train->callback([t, &global] { RunHgvaeTrain(*t, global); });
  AddHgvaeSampleCommand(*hg, global);
  AddHgvaeEvalCommand(*hg, global);
}

}  // namespace motionfork::app
