// motionfork train: train a generator from a model config on a protocol's training split.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app_common.h"
#include "bundle/generator_bundle.h"
#include "bundle/prior_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "constraints/torch/angle_penalty.h"
#include "core/error.h"
#include "dataset/dataset.h"
#include "dataset_loading.h"
#include "flow/flow_module.h"
#include "flow/pose_prior.h"
#include "generator/training/training.h"
#include "io/file_util.h"
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

// The split a run trains on, as recorded: the split file's absolute path, or the protocol's own.
std::string SplitName(const TrainOptions& o) {
  return o.split_file.empty() ? "the protocol's own"
                              : std::filesystem::absolute(o.split_file).string();
}

// The whole recipe travels with the weights: OUT/training.yaml holds a header (the config's path,
// the split, what --epochs changed) and, after kConfigMark, the config file as read. A folder
// that has trained epochs is refused for another config or split (resuming would mix two recipes
// in one model); --epochs may differ, to train longer. Called before any data is read.
void RecordTrainingConfig(const TrainOptions& o, const std::string& config_path) {
  namespace fs = std::filesystem;
  static const std::string kConfigMark = "# --- the config file as read ---\n";
  const std::string body = ReadFileBytes(config_path);
  const std::string split_line = "# split: " + SplitName(o) + "\n";
  const fs::path recorded = fs::path(o.out) / "training.yaml";
  const bool trained = fs::is_regular_file(fs::path(o.out) / "checkpoint" / "state.pt");
  if (trained && fs::is_regular_file(recorded)) {
    const std::string before = ReadFileBytes(recorded.string());
    const size_t mark = before.find(kConfigMark);
    const bool same_config =
        mark != std::string::npos &&
        before.compare(mark + kConfigMark.size(), std::string::npos, body) == 0;
    const size_t split_at = before.find(split_line);
    if (!same_config || split_at == std::string::npos || split_at > mark) {
      throw FormatError(
          FormatMessage(recorded.string(), "",
                        std::string("this folder's epochs were trained with another ") +
                            (same_config ? "split" : "config") + " than now (" +
                            (same_config ? SplitName(o) : config_path) +
                            "); resume with the config and split recorded here (--epochs may "
                            "differ), or train into a new "
                            "--out"));
    }
  }
  std::string header = "# The training config of this bundle: " + config_path +
                       ", read by `motionfork train`.\n" + split_line;
  if (o.epochs > 0) {
    header +=
        "# --epochs " + std::to_string(o.epochs) +
        " on the command line replaced training.epochs (and capped lr_constant_epochs at it).\n";
  }
  if (trained && !fs::is_regular_file(recorded)) {
    header += "# Recorded when resuming: the config of the earlier epochs was not recorded.\n";
  }
  fs::create_directories(o.out);
  WriteFileAtomically(recorded.string(), header + kConfigMark + body);
}

void RunTrain(const TrainOptions& o, const GlobalOptions& g) {
  const std::string config_dir = ConfigDir(g.config_dir);
  const std::string config_path = ResolveConfigPath(config_dir, "models", o.config);
  GeneratorTrainConfig cfg = LoadGeneratorTrainConfig(config_path);
  if (o.epochs > 0) {
    cfg.training.epochs = o.epochs;
    cfg.training.lr_constant_epochs = std::min(cfg.training.lr_constant_epochs, o.epochs);
  }
  RecordTrainingConfig(o, config_path);  // before the data: a refused folder costs nothing
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
  model.info["split"] = SplitName(o);
  model.info["training_config"] = "training.yaml";

  LossHooks hooks;
  std::shared_ptr<AnglePenalty> penalty;
  std::string constraints_path, prior_dir;  // copied into the bundle: it describes itself
  if (!cfg.constraints.empty()) {
    const std::string path = ResolveConfigPath(config_dir, "constraints", cfg.constraints);
    constraints_path = path;
    const ConstraintSet set = ConstraintSet::Build(LoadConstraintConfig(path), *skeleton.skeleton);
    penalty = std::make_shared<AnglePenalty>(set);
    // Predicted poses are root-relative without the root: put the root back at the origin.
    hooks.angle_penalty = [penalty](const torch::Tensor& poses) {
      auto sizes = poses.sizes().vec();
      sizes[sizes.size() - 2] = 1;
      return (*penalty)->forward(torch::cat({torch::zeros(sizes), poses}, -2));
    };
    std::printf("angle loss: %d constraints from %s\n", set.num_constraints(), path.c_str());
  }
  std::shared_ptr<PosePrior> prior;
  if (!cfg.prior.empty()) {
    namespace fs = std::filesystem;
    // Relative prior paths are taken from the source tree's root (where models/ lives) when they
    // do not exist from the working directory.
    std::string dir = cfg.prior;
    const fs::path from_tree = fs::path(config_dir).parent_path() / dir;
    if (!fs::is_directory(dir) && fs::is_directory(from_tree)) dir = from_tree.string();
    prior = std::make_shared<PosePrior>(LoadPosePrior(dir));
    prior->CheckSkeleton(*skeleton.skeleton);
    prior->module()->Freeze();
    const std::vector<int> parents = skeleton.skeleton->parents();
    // Poses [M, N, 3] (root-relative, no root) -> unit limb directions -> mean NLL.
    hooks.prior_nll = [prior, parents](const torch::Tensor& poses) {
      return -prior->module()->log_prob(LimbDirectionsRootRelative(poses, parents)).mean();
    };
    std::printf("prior loss: %s\n", dir.c_str());
    prior_dir = dir;
  }
  AttachToBundle(o.out, constraints_path, prior_dir);
  TrainCallbacks cb;
  std::unique_ptr<ProgressBar> bar;
  cb.step = [&](int epoch, double fraction,
                const std::vector<std::pair<std::string, double>>& terms) {
    if (!bar)
      bar = std::make_unique<ProgressBar>(
          "epoch " + std::to_string(epoch + 1) + "/" + std::to_string(cfg.training.epochs),
          !g.quiet);
    // Every loss term, in short: "loss 0.43 rec 0.0011 limb 0.0002 div0 0.0063 ...".
    std::string detail;
    for (const auto& [name, v] : terms) {
      char buf[48];
      std::snprintf(buf, sizeof(buf), "%s%s %.3g", detail.empty() ? "" : " ",
                    ShortTermName(name).c_str(), v);
      detail += buf;
    }
    bar->Update(fraction, detail);
  };
  cb.epoch = [&](int epoch, const std::vector<std::pair<std::string, double>>& terms,
                 double seconds) {
    bar.reset();
    std::printf("epoch %d/%d (%s):", epoch + 1, cfg.training.epochs, Duration(seconds).c_str());
    for (const auto& [name, v] : terms) std::printf(" %s %.4g", name.c_str(), v);
    std::printf("\n");
    std::fflush(stdout);
  };
  cb.message = [](const std::string& m) { std::printf("%s\n", m.c_str()); };
  const TrainSummary s = TrainGenerator(cfg, model, data, o.out, hooks, cb, o.stop_after);
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
