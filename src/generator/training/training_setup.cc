#include "generator/training/training_setup.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "bundle/prior_bundle.h"
#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "constraints/torch/angle_penalty.h"
#include "core/error.h"
#include "flow/flow_module.h"
#include "flow/pose_prior.h"
#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

std::string TrainingSplitName(const std::string& split_file) {
  return split_file.empty() ? "the protocol's own" : fs::absolute(split_file).string();
}

namespace {

// A config's text without its top-level `trajectory:` section (the key's line and the indented,
// blank or comment lines after it): the part of a config that shapes the generator's epochs.
std::string WithoutTrajectorySection(const std::string& config) {
  std::istringstream in(config);
  std::string kept, line;
  bool inside = false;
  while (std::getline(in, line)) {
    const bool top_level = !line.empty() && line[0] != ' ' && line[0] != '\t' && line[0] != '#';
    if (top_level) inside = line.rfind("trajectory:", 0) == 0;
    if (!inside) kept += line + "\n";
  }
  return kept;
}

}  // namespace

void RecordTrainingConfig(const std::string& out, const std::string& config_path,
                          const std::string& split_file, int epochs, const std::string& precision) {
  static const std::string kConfigMark = "# --- the config file as read ---\n";
  const std::string body = ReadFileBytes(config_path);
  const std::string split_line = "# split: " + TrainingSplitName(split_file) + "\n";
  const fs::path recorded = fs::path(out) / "training.yaml";
  const bool trained = fs::is_regular_file(fs::path(out) / "checkpoint" / "state.pt");
  if (trained && fs::is_regular_file(recorded)) {
    const std::string before = ReadFileBytes(recorded.string());
    const size_t mark = before.find(kConfigMark);
    // A trajectory section may come or change: it trains after the generator's epochs.
    const bool same_config = mark != std::string::npos &&
                             WithoutTrajectorySection(before.substr(mark + kConfigMark.size())) ==
                                 WithoutTrajectorySection(body);
    const size_t split_at = before.find(split_line);
    if (!same_config || split_at == std::string::npos || split_at > mark) {
      throw FormatError(FormatMessage(
          recorded.string(), "",
          std::string("this folder's epochs were trained with another ") +
              (same_config ? "split" : "config") + " than now (" +
              (same_config ? TrainingSplitName(split_file) : config_path) +
              "); resume with the config and split recorded here (--epochs may differ), or "
              "train into a new --out"));
    }
  }
  std::string header = "# The training config of this bundle: " + config_path +
                       ", read by `motionfork train`.\n" + split_line;
  if (epochs > 0) {
    header +=
        "# --epochs " + std::to_string(epochs) +
        " on the command line replaced training.epochs (and scaled lr_constant_epochs with it: "
        "the same share of the run).\n";
  }
  if (!precision.empty()) {
    header += "# --precision " + precision + " on the command line replaced training.precision.\n";
  }
  if (trained && !fs::is_regular_file(recorded)) {
    header += "# Recorded when resuming: the config of the earlier epochs was not recorded.\n";
  }
  fs::create_directories(out);
  WriteFileAtomically(recorded.string(), header + kConfigMark + body);
}

void OverrideEpochs(TrainingOptions* t, int epochs) {
  if (epochs <= 0) throw std::invalid_argument("--epochs must be positive");
  const double share = t->epochs > 0 ? static_cast<double>(t->lr_constant_epochs) / t->epochs : 1;
  t->lr_constant_epochs = std::clamp(static_cast<int>(std::lround(share * epochs)), 0, epochs);
  t->epochs = epochs;
}

std::string FindPriorBundle(const std::string& prior, const std::string& config_dir) {
  const fs::path from_tree = fs::path(config_dir).parent_path() / prior;
  if (!fs::is_directory(prior) && fs::is_directory(from_tree)) return from_tree.string();
  return prior;
}

bool PriorBundleExists(const std::string& prior, const std::string& config_dir) {
  return fs::exists(fs::path(FindPriorBundle(prior, config_dir)) / "prior.yaml");
}

LossHookSources MakeLossHooks(const GeneratorTrainConfig& cfg, const Skeleton& skeleton,
                              const std::string& config_dir) {
  LossHookSources s;
  if (!cfg.constraints.empty()) {
    s.constraints_path = ResolveConfigPath(config_dir, "constraints", cfg.constraints);
    const ConstraintSet set =
        ConstraintSet::Build(LoadConstraintConfig(s.constraints_path), skeleton);
    s.constraints = set.num_constraints();
    auto penalty = std::make_shared<AnglePenalty>(set);
    // Predicted poses are root-relative without the root: put the root back at the origin.
    s.hooks.angle_penalty = [penalty](const torch::Tensor& poses) {
      auto sizes = poses.sizes().vec();
      sizes[sizes.size() - 2] = 1;
      return (*penalty)->forward(torch::cat({torch::zeros(sizes), poses}, -2));
    };
  }
  if (!cfg.prior.empty()) {
    s.prior_dir = FindPriorBundle(cfg.prior, config_dir);
    auto prior = std::make_shared<PosePrior>(LoadPosePrior(s.prior_dir));
    prior->CheckSkeleton(skeleton);
    prior->module()->Freeze();
    const std::vector<int> parents = skeleton.parents();
    // Poses [M, N, 3] (root-relative, no root) -> unit limb directions -> mean NLL.
    s.hooks.prior_nll = [prior, parents](const torch::Tensor& poses) {
      return -prior->module()->log_prob(LimbDirectionsRootRelative(poses, parents)).mean();
    };
  }
  return s;
}

}  // namespace motionfork
