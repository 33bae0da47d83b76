// motionfork train: train a generator from a model config on a protocol's training split.
#include <cstdio>
#include <memory>

#include "app_common.h"
#include "bundle/generator_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "dataset_loading.h"
#include "generator/model/generator_options.h"
#include "generator/model/training_options.h"
#include "generator/training/training.h"
#include "generator/training/training_setup.h"
#include "validity/pose_validator.h"

namespace motionfork::app {
namespace {

struct TrainOptions {
  std::string config;
  std::string data;
  std::string out;
  std::string split_file;
  int epochs = 0;  // override
  int stop_after = 0;
};

// Loss term names as the progress bar shows them.
std::string ShortTermName(const std::string& name) {
  static const std::pair<const char*, const char*> kShort[] = {
      {"total", "loss"},       {"past_reconstruction", "past"},
      {"limb_length", "limb"}, {"diversity_", "div"},
      {"best_of_many", "bom"}, {"multimodal", "mm"},
      {"prior_nll", "prior"},  {"angle", "angle"}};
  for (const auto& [full, brief] : kShort) {
    if (name.rfind(full, 0) == 0) return brief + name.substr(std::string(full).size());
  }
  return name;
}

// Per-step progress bar and per-epoch lines.
TrainCallbacks EpochReports(int epochs, const GlobalOptions& g, std::unique_ptr<ProgressBar>* bar) {
  TrainCallbacks cb;
  cb.step = [bar, epochs, &g](int epoch, double fraction,
                              const std::vector<std::pair<std::string, double>>& terms) {
    if (!*bar)
      *bar = std::make_unique<ProgressBar>(
          "epoch " + std::to_string(epoch + 1) + "/" + std::to_string(epochs), !g.quiet);
    // Every loss term, in short: "loss 0.43 rec 0.0011 limb 0.0002 div0 0.0063 ...".
    std::string detail;
    for (const auto& [name, v] : terms) {
      char buf[48];
      std::snprintf(buf, sizeof(buf), "%s%s %.3g", detail.empty() ? "" : " ",
                    ShortTermName(name).c_str(), v);
      detail += buf;
    }
    (*bar)->Update(fraction, detail);
  };
  cb.epoch = [bar, epochs](int epoch, const std::vector<std::pair<std::string, double>>& terms,
                           double seconds) {
    bar->reset();
    std::printf("epoch %d/%d (%s):", epoch + 1, epochs, Duration(seconds).c_str());
    for (const auto& [name, v] : terms) std::printf(" %s %.4g", name.c_str(), v);
    std::printf("\n");
    std::fflush(stdout);
  };
  cb.message = [](const std::string& m) { std::printf("%s\n", m.c_str()); };
  return cb;
}

void RunTrain(const TrainOptions& o, const GlobalOptions& g) {
  const std::string config_dir = ConfigDir(g.config_dir);
  const std::string config_path = ResolveConfigPath(config_dir, "models", o.config);
  GeneratorTrainConfig cfg = LoadGeneratorTrainConfig(config_path);
  if (o.epochs > 0) {
    cfg.training.epochs = o.epochs;
    cfg.training.lr_constant_epochs = std::min(cfg.training.lr_constant_epochs, o.epochs);
  }
  RecordTrainingConfig(o.out, config_path, o.split_file,
                       o.epochs);  // before the data: a refused folder costs nothing
  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", cfg.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", protocol.skeleton));
  const Dataset ds = LoadDatasetWithProgress(protocol, skeleton, o.data, o.split_file, g);
  TrainingWindows data;
  {
    ProgressBar bar("pseudo multimodal futures", !g.quiet);
    data = BuildTrainingWindows(ds, cfg.training.window_stride, cfg.multimodal,
                                CacheDir(g.cache_dir), [&bar](double f) { bar.Update(f); });
  }
  size_t with_mm = 0;
  for (const auto& m : data.multimodal) with_mm += !m.empty();
  std::printf("training windows: %zu (stride %d), %zu with pseudo multimodal futures\n",
              data.windows.size(), cfg.training.window_stride, with_mm);

  ModelConfig model;
  model.protocol = protocol.name;
  model.fps = protocol.fps;
  model.generator = cfg.generator;
  model.generator.t_his = protocol.t_his;
  model.generator.t_pred = protocol.t_pred;
  model.generator.num_nodes = skeleton.skeleton->num_joints() - 1;
  model.skeleton = skeleton.skeleton->ToSpec();
  model.info["config"] = cfg.name;
  model.info["seed"] = std::to_string(cfg.training.seed);
  model.info["epochs"] = std::to_string(cfg.training.epochs);
  model.info["split"] = TrainingSplitName(o.split_file);
  model.info["training_config"] = "training.yaml";

  const LossHookSources losses = MakeLossHooks(cfg, *skeleton.skeleton, config_dir);
  if (!losses.constraints_path.empty()) {
    std::printf("angle loss: %d constraints from %s\n", losses.constraints,
                losses.constraints_path.c_str());
  }
  if (!losses.prior_dir.empty()) std::printf("prior loss: %s\n", losses.prior_dir.c_str());
  AttachToBundle(o.out, losses.constraints_path, losses.prior_dir);
  std::unique_ptr<ProgressBar> bar;
  const TrainCallbacks cb = EpochReports(cfg.training.epochs, g, &bar);
  const TrainSummary s = TrainGenerator(cfg, model, data, o.out, losses.hooks, cb, o.stop_after);
  if (s.first_epoch >= cfg.training.epochs) {
    std::printf(
        "all %d epochs were trained already; bundle: %s (constraints.yaml and prior/ copied "
        "again), log: "
        "%s/log.csv\n",
        cfg.training.epochs, o.out.c_str(), o.out.c_str());
    return;
  }
  std::printf(
      "trained epochs %d..%d in %s; bundle: %s (model.yaml, generator.pt), log: %s/log.csv\n",
      s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(), o.out.c_str(), o.out.c_str());
}

}  // namespace

void AddTrainCommand(CLI::App& app, GlobalOptions& global) {
  auto o = std::make_shared<TrainOptions>();
  CLI::App* cmd = app.add_subcommand(
      "train",
      "Train a generator (configs/models/NAME.yaml) on a protocol's training split.\n"
      "Every epoch writes the bundle (OUT/model.yaml, OUT/generator.pt; OUT/constraints.yaml and\n"
      "OUT/prior/ when the config names them), a row of OUT/log.csv and a checkpoint; "
      "OUT/training.yaml\n"
      "records the config as read and the split. Running the same command again resumes where it\n"
      "stopped (--epochs may change; another config or split is refused).");
  cmd->add_option("--config", o->config, "Model config name (configs/models/) or YAML path")
      ->required();
  cmd->add_option("--data", o->data, "Data folder of the config's protocol")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", o->out, "Output folder (bundle, log, checkpoint)")->required();
  cmd->add_option("--split", o->split_file, "Split file overriding the protocol's");
  cmd->add_option("--epochs", o->epochs, "Override the config's epoch count")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--stop-after", o->stop_after,
                  "Stop after this many epochs of this run (resume later)")
      ->check(CLI::PositiveNumber);
  cmd->callback([o, &global] { RunTrain(*o, global); });
}

}  // namespace motionfork::app
