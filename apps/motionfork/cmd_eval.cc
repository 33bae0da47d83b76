// motionfork eval: a predictor on a protocol's test windows -> APD, ADE, FDE, MMADE, MMFDE,
// overall and per action (generator/training/eval_experiment.h does the work).
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "generator/training/eval_experiment.h"
#include "generator/training/eval_experiment_json.h"
#include "generator/training/eval_experiment_text.h"
#include "pipeline/motion_input.h"

namespace motionfork::app {
namespace {

struct EvalCommandOptions {
  EvalExperimentOptions experiment;
  std::string split;  // a split FILE, or (deprecated) a subset name
  bool no_repair = false;
  std::string json;
};

void RunEval(EvalCommandOptions o, const GlobalOptions& g) {
  EvalExperimentOptions& e = o.experiment;
  const bool subset_name = o.split == "test" || o.split == "train" || o.split == "all";
  if (subset_name && !std::filesystem::exists(o.split)) {
    NoteDeprecated("--split " + o.split, "--subset " + o.split);
    e.subset = o.split;
  } else if (!o.split.empty()) {
    e.split_file = o.split;
  }
  e.repair = !o.no_repair;
  e.config_dir = ConfigDir(g.config_dir);
  e.models_dir = (std::filesystem::path(MOTIONFORK_CONFIG_DIR).parent_path() / "models").string();
  e.cache_dir = CacheDir(g.cache_dir);
  if (!e.clips.empty()) e.conform_clips = pipeline::ConformClipsByRoles(e.config_dir, e.protocol);
  StageBars bars(!g.quiet);
  e.progress = bars.Callback();
  const EvalExperiment x = RunEvalExperiment(e);
  bars.Finish();
  PrintText(EvalExperimentText(o.experiment, x));
  if (!o.json.empty()) EmitJson(o.json, EvalExperimentJson(o.experiment, x));
}

}  // namespace

void AddEvalCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<EvalCommandOptions>(
      &app, global, RunEval, "eval",
      "Evaluate a predictor on a protocol's test windows: APD, ADE, FDE, MMADE, MMFDE (metres, "
      "whole pose vectors, K samples per history), overall and per action.");
  EvalExperimentOptions& e = o->experiment;
  cmd->add_option("--baseline", e.baseline,
                  "Non-learned predictor: zero-velocity (every sample repeats the last pose), "
                  "constant-velocity (the last pose carried on at the root's velocity) or "
                  "nearest-neighbours (K training futures, stride-5 windows, re-targeted)");
  cmd->add_option("--velocity-frames", e.velocity.frames,
                  "constant-velocity: frame steps its velocity is a mean over (default 0: the "
                  "whole history)")
      ->check(NonNegativeNumber);
  cmd->add_flag("--velocity-turn", e.velocity.turn,
                "constant-velocity: keep turning at the pelvis's turn rate too");
  cmd->add_option("--model", e.model, "Trained model bundle folder (model.yaml + generator.pt)");
  cmd->add_option("--protocol", e.protocol, "Protocol name (bandai, h36m, humaneva) or YAML path")
      ->required();
  cmd->add_option("--data", e.data,
                  "The protocol's data folder: test clips of --subset and the training clips")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--subset", e.subset, "Clips of --data to evaluate: test (default), train or all")
      ->check(CLI::IsMember({"test", "train", "all"}));
  cmd->add_option("--split", o->split, "Split file overriding the protocol's split.file");
  AddDeprecatedOption(cmd, "--split-file", "--split FILE", &e.split_file);
  cmd->add_option("--clips", e.clips,
                  "Evaluate this folder of .bvh/.npy/.csv files instead (training clips still "
                  "come from --data)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--turn", e.turn_degrees,
                  "Turn the test clips by this many degrees about the protocol's up axis first "
                  "(how the predictor fares on bodies facing another way; training clips stay)");
  cmd->add_option("-k", e.k, "Futures per history (K, >= 2; default 50)");
  AddDeprecatedOption(cmd, "--samples", "-k", &e.k);
  cmd->add_option("--seed", e.seed, "Seed (window i uses a mix of it and i)")->check(Seed);
  cmd->add_option(
      "--constraints", e.constraints,
      "Constraint set for the angle-violation rate (default: the protocol's shipped set; "
      "'none' to skip)");
  cmd->add_option("--prior", e.prior,
                  "Prior bundle for the prior NLL (default: models/prior-<protocol> when shipped; "
                  "'none' to skip)");
  cmd->add_option("--fix", e.fix,
                  "Controllable setting: a part of the skeleton's default partition (e.g. legs) "
                  "that every sample shares; reports the APD of the varied and the fixed joints");
  cmd->add_flag(
      "--no-repair", o->no_repair,
      "With --model: score the network's raw futures, without moving poses that break the "
      "bundle's angle ranges back inside them");
  AddThreadsOption(cmd, &e.threads);
  AddPrecisionOption(cmd, &e.precision);
  AddJsonOption(cmd, &o->json, "Every figure");
}

}  // namespace motionfork::app
