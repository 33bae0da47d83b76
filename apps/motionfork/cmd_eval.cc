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

namespace motionfork::app {
namespace {

struct EvalCommandOptions {
  EvalExperimentOptions experiment;
  std::string split;  // a split FILE, or (deprecated) a subset name
  bool no_repair = false;
  std::string json;
};

void PrintRow(const std::string& label, const Figures& f, bool fixed) {
  std::printf("%-24s %8s %7.3f %7.3f %7.3f %7.3f %7.3f %9.1f", label.c_str(),
              WithThousands(f.windows).c_str(), f.apd, f.ade, f.fde, f.mmade, f.mmfde,
              f.mean_set_size);
  if (fixed) std::printf(" %10.3f %9.3f", f.apd_varied, f.apd_fixed);
  std::printf("\n");
}

void PrintHeader(const EvalCommandOptions& o, const EvalExperiment& x) {
  const ProtocolOptions& p = x.protocol;
  const EvalResult& r = x.result;
  if (!x.scorers_described.empty()) {
    std::printf("plausibility figures: %s\n", x.scorers_described.c_str());
  }
  std::printf("protocol:   %s (%s), %.6g Hz, t_his %d, t_pred %d\n", p.name.c_str(), p.path.c_str(),
              p.fps, p.t_his, p.t_pred);
  std::printf("test:       %s: %s windows from %s clips (stride %d, %s)\n", x.test_source.c_str(),
              WithThousands(x.windows).c_str(), WithThousands(x.clips).c_str(), p.test_stride,
              p.test_include_last ? "last start included" : "last start excluded");
  std::printf(
      "multimodal: threshold %.6g m on the last history pose, mean set size %.1f, %s (%s)\n",
      p.multimodal_threshold, r.overall.mean_set_size,
      p.keep_singleton_sets
          ? "singleton sets kept"
          : ("singleton sets skipped: " + WithThousands(r.windows_skipped) + " windows").c_str(),
      x.multimodal_cached ? "from the cache" : "computed");
  std::printf("predictor:  %s%s%s\n", x.predictor_name.c_str(),
              x.predictor_description.empty() ? "" : ": ", x.predictor_description.c_str());
  std::printf("samples:    K = %d, seed %llu%s\n", o.experiment.k,
              static_cast<unsigned long long>(o.experiment.seed),
              r.fixed_part.empty()
                  ? ""
                  : (", fixed part '" + r.fixed_part + "' (shared by every sample)").c_str());
  if (x.overlaps_training) {
    std::printf(
        "note:       the evaluated windows overlap the nearest-neighbour training windows\n");
  }
}

void PrintTable(const EvalExperiment& x) {
  const EvalResult& r = x.result;
  const bool fixed = !r.fixed_part.empty();
  std::printf("\n%-24s %8s %7s %7s %7s %7s %7s %9s", "action", "windows", "APD", "ADE", "FDE",
              "MMADE", "MMFDE", "mm set");
  if (fixed) std::printf(" %10s %9s", "APD varied", "APD fixed");
  std::printf("\n");
  PrintRow("all", r.overall, fixed);
  if (x.actions.size() > 1 || (x.actions.size() == 1 && !x.actions[0].empty())) {
    for (size_t a = 0; a < x.actions.size(); ++a) {
      if (r.per_action[a].windows == 0) continue;
      PrintRow(x.actions[a].empty() ? "(unlabelled)" : x.actions[a], r.per_action[a], fixed);
    }
  }
  const double measured = r.seconds_predicting + r.seconds_metrics + r.seconds_scoring;
  std::printf(
      "\nmetres; APD, ADE, FDE: whole pose vectors (%d numbers a frame), min over samples\n",
      x.pose_dims);
  std::printf(
      "time:       %s in all: loading %s, test windows + multimodal sets %s, predictor setup "
      "%s,\n            predictor %s (%.0f%%), metrics %s (%.0f%%)\n",
      Duration(x.seconds_total).c_str(), Duration(x.seconds_loading).c_str(),
      Duration(x.seconds_multimodal).c_str(), Duration(x.seconds_predictor_setup).c_str(),
      Duration(r.seconds_predicting).c_str(),
      measured > 0 ? 100 * r.seconds_predicting / measured : 0.0,
      Duration(r.seconds_metrics).c_str(), measured > 0 ? 100 * r.seconds_metrics / measured : 0.0);
}

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
  StageBars bars(!g.quiet);
  e.progress = bars.Callback();
  const EvalExperiment x = RunEvalExperiment(e);
  bars.Finish();
  PrintHeader(o, x);
  PrintTable(x);
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
                  "Non-learned predictor: zero-velocity (every sample repeats the last pose) or "
                  "nearest-neighbours (K training futures, stride-5 windows, re-targeted)");
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
  cmd->add_option("-k", e.k, "Futures per history (K, >= 2; default 50)");
  AddDeprecatedOption(cmd, "--samples", "-k", &e.k);
  cmd->add_option("--seed", e.seed, "Seed (window i uses a mix of it and i)");
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
  AddJsonOption(cmd, &o->json, "Every figure");
}

}  // namespace motionfork::app
