// motionfork eval: a predictor on a protocol's test windows -> APD, ADE, FDE, MMADE, MMFDE,
// overall and per action, with a JSON copy of every figure.
//
// Predictors come from MakePredictor below: the baselines now; a trained generator plugs in there
// (a `--model DIR` branch building its Predictor from the bundle).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "app_common.h"
#include "bundle/generator_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "dataset_loading.h"
#include "eval/baselines.h"
#include "eval/clip_folder.h"
#include "eval/evaluate.h"
#include "eval/test_set.h"
#include "generator/inference/forecaster.h"
#include "generator/training/generator_predictor.h"
#include "io/file_util.h"
#include "validity/pose_validator.h"

namespace motionfork::app {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct EvalCommandOptions {
  std::string baseline;
  std::string model;
  std::string protocol;
  std::string data;
  std::string split = "test";
  std::string split_file;
  std::string clips;
  int k = 50;
  uint64_t seed = 0;
  std::string fix;
  bool no_repair = false;
  std::string json;
  std::string constraints;  // "" = the protocol's shipped set when there is one; "none" = off
  std::string prior;        // "" = models/prior-<protocol> when shipped; "none" = off
};

// Plausibility scorers: angle-violation rate (any constraint outside its range in a frame) and
// prior NLL (nats per pose). Both are optional; their sources are printed in the table header.
struct Scorers {
  std::unique_ptr<PoseValidator> validator;
  std::vector<FrameScorer> list;
  std::string described;
};

void AddScorers(const EvalCommandOptions& o, const ProtocolOptions& p,
                const std::shared_ptr<const Skeleton>& skeleton, const std::string& config_dir,
                Scorers* out) {
  namespace fs = std::filesystem;
  std::string constraints = o.constraints;
  if (constraints.empty() &&
      fs::is_regular_file(fs::path(config_dir) / "constraints" / (p.name + ".yaml"))) {
    constraints = p.name;
  }
  const std::string constraints_path =
      !constraints.empty() && constraints != "none"
          ? ResolveConfigPath(config_dir, "constraints", constraints)
          : "";
  std::string prior = o.prior;
  const fs::path shipped =
      fs::path(MOTIONFORK_CONFIG_DIR).parent_path() / "models" / ("prior-" + p.name);
  if (prior.empty() && fs::is_directory(shipped)) prior = shipped.string();
  if (prior == "none") prior.clear();
  out->validator = std::make_unique<PoseValidator>(skeleton, p.fps, constraints_path, prior);
  const PoseValidator* v = out->validator.get();
  auto copy = [](const std::vector<double>& from, double* to) {
    std::copy(from.begin(), from.end(), to);
  };
  if (v->has_constraints()) {
    out->list.push_back(
        FrameScorer{"angle_violation_rate", [v, copy](const float* pos, int n, double* scores) {
                      copy(v->ViolationFlags(pos, n), scores);
                    }});
  }
  if (v->has_prior()) {
    out->list.push_back(FrameScorer{
        "prior_nll",
        [v, copy](const float* pos, int n, double* scores) { copy(v->PriorNll(pos, n), scores); }});
  }
  out->described = v->described();
}

const char* const kBaselines = "zero-velocity, nearest-neighbours";

std::string CanonicalBaseline(const std::string& name) {
  if (name == "zero-velocity" || name == "zero") return "zero-velocity";
  if (name == "nearest-neighbours" || name == "nearest-neighbors" || name == "nn") {
    return "nearest-neighbours";
  }
  throw std::invalid_argument("--baseline: unknown baseline '" + name + "'; expected one of " +
                              kBaselines);
}

std::string Json(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string Num(double v, const char* format = "%.6f") {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

// The figures of one group as JSON members (no braces); the window count unless the caller
// writes its own.
std::string FigureMembers(const Figures& f, bool fixed, const std::vector<FrameScorer>& scorers,
                          bool with_windows = true) {
  std::string j = with_windows ? "\"windows\": " + std::to_string(f.windows) + ", " : "";
  j += "\"apd\": " + Num(f.apd) + ", \"ade\": " + Num(f.ade) + ", \"fde\": " + Num(f.fde) +
       ", \"mmade\": " + Num(f.mmade) + ", \"mmfde\": " + Num(f.mmfde) +
       ", \"mean_multimodal_set_size\": " + Num(f.mean_set_size, "%.3f");
  if (fixed) j += ", \"apd_varied\": " + Num(f.apd_varied) + ", \"apd_fixed\": " + Num(f.apd_fixed);
  for (size_t s = 0; s < scorers.size() && s < f.predicted_scores.size(); ++s) {
    j += ", " + Json(scorers[s].name) + ": " + Num(f.predicted_scores[s]) + ", " +
         Json(scorers[s].name + "_gt") + ": " + Num(f.truth_scores[s]);
  }
  return j;
}

void PrintRow(const std::string& label, const Figures& f, bool fixed) {
  std::printf("%-24s %8s %7.3f %7.3f %7.3f %7.3f %7.3f %9.1f", label.c_str(),
              WithThousands(f.windows).c_str(), f.apd, f.ade, f.fde, f.mmade, f.mmfde,
              f.mean_set_size);
  if (fixed) std::printf(" %10.3f %9.3f", f.apd_varied, f.apd_fixed);
  std::printf("\n");
}

// The predictor a command line asks for. training: the protocol's training clips (for the
// nearest-neighbour baseline); they outlive the predictor.
std::unique_ptr<Predictor> MakePredictor(const EvalCommandOptions& o, const ProtocolOptions& p,
                                         const std::shared_ptr<const Skeleton>& skeleton,
                                         const std::vector<const Motion*>& training) {
  if (!o.model.empty()) {
    Forecaster f = LoadForecaster(o.model);
    const ModelConfig& mc = f.config();
    if (!f.skeleton()->SameStructure(*skeleton) || mc.generator.t_his != p.t_his ||
        mc.generator.t_pred != p.t_pred) {
      throw std::invalid_argument(
          "--model " + o.model + " was trained for protocol '" + mc.protocol + "' (skeleton '" +
          f.skeleton()->name() + "', t_his " + std::to_string(mc.generator.t_his) + ", t_pred " +
          std::to_string(mc.generator.t_pred) + "), not for '" + p.name + "' (skeleton '" +
          skeleton->name() + "', t_his " + std::to_string(p.t_his) + ", t_pred " +
          std::to_string(p.t_pred) + ")");
    }
    const std::string name = mc.info.count("config") ? mc.info.at("config") : std::string("model");
    return std::make_unique<GeneratorPredictor>(std::move(f), name, GeneratorBundleHash(o.model),
                                                !o.no_repair);
  }
  const std::string name = CanonicalBaseline(o.baseline);
  if (name == "zero-velocity") {
    return std::make_unique<ZeroVelocityPredictor>(skeleton, p.t_his, p.t_pred);
  }
  if (o.data.empty()) {
    throw std::invalid_argument(
        "--baseline nearest-neighbours needs --data DIR: its training "
        "clips are the protocol's train split");
  }
  if (training.empty()) {
    throw std::invalid_argument(
        "--baseline nearest-neighbours needs training clips: the train split "
        "of " +
        o.data + " has no clip of at least " + std::to_string(p.window_length()) + " frames");
  }
  NearestNeighbourOptions nn;  // the definition: stride 5; include_last as SlidingWindows
  return std::make_unique<NearestNeighbourPredictor>(training, p.t_his, p.t_pred, nn);
}

void RunEval(const EvalCommandOptions& o, GlobalOptions& g) {
  const auto start_all = Clock::now();
  if (o.baseline.empty() == o.model.empty()) {
    throw std::invalid_argument("give one of --baseline NAME (" + std::string(kBaselines) +
                                ") or --model DIR");
  }
  if (o.k < 2) {
    throw std::invalid_argument(
        "-k: expected K >= 2 samples per history (APD is a mean over pairs "
        "of samples), got " +
        std::to_string(o.k));
  }
  if (o.split != "test" && o.split != "train" && o.split != "all") {
    throw std::invalid_argument("--split: expected test, train or all, got '" + o.split + "'");
  }
  if (o.data.empty() && o.clips.empty()) {
    throw std::invalid_argument("give --data DIR (the protocol's dataset) and/or --clips DIR");
  }
  // Fail before loading anything.
  if (!o.model.empty()) LoadForecaster(o.model);
  if (!o.baseline.empty() && CanonicalBaseline(o.baseline) == "nearest-neighbours" &&
      o.data.empty()) {
    throw std::invalid_argument(
        "--baseline nearest-neighbours needs --data DIR: its training "
        "clips are the protocol's train split");
  }
  if (!o.split_file.empty() && !std::filesystem::is_regular_file(o.split_file)) {
    throw std::invalid_argument("--split-file: '" + o.split_file + "' is not a file");
  }
  const std::string config_dir = ConfigDir(g.config_dir);
  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", o.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", protocol.skeleton));
  int fixed_part = -1;
  if (!o.fix.empty()) {
    const Partition& partition = skeleton.skeleton->GetPartition();
    std::string names;
    for (size_t i = 0; i < partition.parts.size(); ++i) {
      if (partition.parts[i].name == o.fix) fixed_part = static_cast<int>(i);
      names += (i ? ", " : "") + partition.parts[i].name;
    }
    if (fixed_part < 0) {
      throw std::invalid_argument("--fix: skeleton '" + skeleton.skeleton->name() +
                                  "' has no part '" + o.fix + "' in its default partition '" +
                                  partition.name + "'; expected one of " + names);
    }
  }
  if (!o.data.empty() && o.split_file.empty() && !protocol.split_file.empty()) {
    std::filesystem::path split = protocol.split_file;
    if (split.is_relative()) split = std::filesystem::path(o.data) / split;
    if (!std::filesystem::is_regular_file(split)) {
      throw std::invalid_argument("split file '" + split.string() + "' not found (protocol '" +
                                  protocol.name +
                                  "' expects it in the data folder; pass "
                                  "--split-file FILE otherwise)");
    }
  }
  const std::string cache_dir = CacheDir(g.cache_dir);

  // The dataset: test clips (unless --clips) and training clips.
  auto start = Clock::now();
  Dataset ds;
  if (!o.data.empty()) ds = LoadDatasetWithProgress(protocol, skeleton, o.data, o.split_file, g);
  ClipFolder folder;
  std::vector<const Clip*> test_clips;
  std::string test_source;
  if (!o.clips.empty()) {
    ProgressBar bar("reading clips", !g.quiet);
    ClipFolderOptions read;
    read.progress = [&bar](const LoadProgress& p) { bar.Update(p.fraction, p.detail); };
    folder = LoadClipFolder(protocol, skeleton, o.clips, read);
    for (const Clip& c : folder.clips) test_clips.push_back(&c);
    test_source = o.clips;
  } else {
    for (const Clip& c : ds.clips) {
      if (o.split == "all" || (o.split == "test") == (c.split == Split::kTest))
        test_clips.push_back(&c);
    }
    test_source = "split '" + o.split + "' of " + o.data;
  }
  if (test_clips.empty()) {
    int listed = 0;
    for (const SkippedClip& c : o.clips.empty() ? ds.skipped : folder.skipped) {
      listed += !o.clips.empty() || o.split == "all" || c.split == o.split;
    }
    const int min_length = protocol.min_length > 0 ? protocol.min_length : protocol.window_length();
    throw std::invalid_argument("nothing to evaluate: " + test_source +
                                (listed == 0
                                     ? std::string(" holds no clips (check the split file)")
                                     : " holds " + std::to_string(listed) + " clips, none of the " +
                                           std::to_string(min_length) + " frames protocol '" +
                                           protocol.name + "' needs"));
  }
  std::vector<const Motion*> training;
  for (const Clip& c : ds.clips) {
    if (c.split == Split::kTrain) training.push_back(&c.motion);
  }
  const double seconds_loading = Since(start);

  start = Clock::now();
  TestSet ts = BuildTestSet(test_clips, protocol);
  const bool mm_cached =
      AttachMultimodalSets(&ts, protocol.multimodal_threshold, cache_dir, protocol.name);
  const double seconds_multimodal = Since(start);

  start = Clock::now();
  std::unique_ptr<Predictor> predictor = MakePredictor(o, protocol, ts.skeleton, training);
  const double seconds_predictor_setup = Since(start);

  EvalOptions eval;
  eval.num_samples = o.k;
  eval.seed = o.seed;
  eval.fixed_part = fixed_part;
  eval.keep_singleton_sets = protocol.keep_singleton_sets;
  Scorers scorers;
  AddScorers(o, protocol, ts.skeleton, ConfigDir(g.config_dir), &scorers);
  eval.scorers = scorers.list;
  if (!scorers.described.empty())
    std::printf("plausibility figures: %s\n", scorers.described.c_str());
  EvalResult r;
  {
    ProgressBar bar("evaluating " + predictor->name(), !g.quiet);
    eval.progress = [&bar](int done, int total) { bar.Update(double(done) / total); };
    r = Evaluate(*predictor, ts, eval);
  }
  const double seconds_total = Since(start_all);
  const bool fixed = fixed_part >= 0;

  std::set<int> clips_used;
  for (const Window& w : ts.windows) clips_used.insert(w.clip);
  std::printf("protocol:   %s (%s), %.6g Hz, t_his %d, t_pred %d\n", protocol.name.c_str(),
              protocol.path.c_str(), protocol.fps, protocol.t_his, protocol.t_pred);
  std::printf("test:       %s: %s windows from %s clips (stride %d, %s)\n", test_source.c_str(),
              WithThousands(ts.num_windows()).c_str(), WithThousands(clips_used.size()).c_str(),
              protocol.test_stride,
              protocol.test_include_last ? "last start included" : "last start excluded");
  std::printf(
      "multimodal: threshold %.6g m on the last history pose, mean set size %.1f, %s (%s)\n",
      protocol.multimodal_threshold, r.overall.mean_set_size,
      protocol.keep_singleton_sets
          ? "singleton sets kept"
          : ("singleton sets skipped: " + WithThousands(r.windows_skipped) + " windows").c_str(),
      mm_cached ? "from the cache" : "computed");
  std::printf("predictor:  %s%s%s\n", predictor->name().c_str(),
              predictor->description().empty() ? "" : ": ", predictor->description().c_str());
  std::printf(
      "samples:    K = %d, seed %llu%s\n", o.k, static_cast<unsigned long long>(o.seed),
      fixed ? (", fixed part '" + r.fixed_part + "' (shared by every sample)").c_str() : "");
  if (o.split != "test" && o.clips.empty() && !o.baseline.empty() &&
      CanonicalBaseline(o.baseline) == "nearest-neighbours") {
    std::printf(
        "note:       the evaluated windows overlap the nearest-neighbour training windows\n");
  }
  std::printf("\n%-24s %8s %7s %7s %7s %7s %7s %9s", "action", "windows", "APD", "ADE", "FDE",
              "MMADE", "MMFDE", "mm set");
  if (fixed) std::printf(" %10s %9s", "APD varied", "APD fixed");
  std::printf("\n");
  PrintRow("all", r.overall, fixed);
  if (ts.actions.size() > 1 || (ts.actions.size() == 1 && !ts.actions[0].empty())) {
    for (size_t a = 0; a < ts.actions.size(); ++a) {
      if (r.per_action[a].windows == 0) continue;
      PrintRow(ts.actions[a].empty() ? "(unlabelled)" : ts.actions[a], r.per_action[a], fixed);
    }
  }
  const double measured = r.seconds_predicting + r.seconds_metrics + r.seconds_scoring;
  std::printf(
      "\nmetres; APD, ADE, FDE: whole pose vectors (%d numbers a frame), min over samples\n",
      ts.pose_dims);
  std::printf(
      "time:       %s in all: loading %s, test windows + multimodal sets %s, predictor setup "
      "%s,\n            predictor %s (%.0f%%), metrics %s (%.0f%%)\n",
      Duration(seconds_total).c_str(), Duration(seconds_loading).c_str(),
      Duration(seconds_multimodal).c_str(), Duration(seconds_predictor_setup).c_str(),
      Duration(r.seconds_predicting).c_str(),
      measured > 0 ? 100 * r.seconds_predicting / measured : 0.0,
      Duration(r.seconds_metrics).c_str(), measured > 0 ? 100 * r.seconds_metrics / measured : 0.0);

  if (!o.json.empty()) {
    std::string j =
        "{\n  \"protocol\": " + Json(protocol.name) +
        ",\n  \"protocol_path\": " + Json(protocol.path) +
        ",\n  \"fps\": " + Num(protocol.fps, "%.6g") +
        ",\n  \"t_his\": " + std::to_string(protocol.t_his) +
        ",\n  \"t_pred\": " + std::to_string(protocol.t_pred) +
        ",\n  \"test_stride\": " + std::to_string(protocol.test_stride) +
        ",\n  \"test_include_last\": " + (protocol.test_include_last ? "true" : "false") +
        ",\n  \"split\": " + (o.clips.empty() ? Json(o.split) : "null") +
        ",\n  \"clips_dir\": " + (o.clips.empty() ? "null" : Json(o.clips)) +
        ",\n  \"clips\": " + std::to_string(clips_used.size()) +
        ",\n  \"windows\": " + std::to_string(ts.num_windows()) +
        ",\n  \"windows_evaluated\": " + std::to_string(r.overall.windows) +
        ",\n  \"windows_skipped_singleton\": " + std::to_string(r.windows_skipped) +
        ",\n  \"multimodal_threshold\": " + Num(protocol.multimodal_threshold, "%.6g") +
        ",\n  \"keep_singleton_sets\": " + (protocol.keep_singleton_sets ? "true" : "false") +
        ",\n  \"k\": " + std::to_string(o.k) + ",\n  \"seed\": " + std::to_string(o.seed) +
        ",\n  \"predictor\": {\"name\": " + Json(predictor->name()) +
        ", \"kind\": " + (o.model.empty() ? "\"baseline\"" : "\"model\"") +
        ", \"description\": " + Json(predictor->description()) + ", \"bundle_hash\": " +
        (predictor->bundle_hash().empty() ? "null" : Json(predictor->bundle_hash()));
    if (const auto* nn = dynamic_cast<const NearestNeighbourPredictor*>(predictor.get())) {
      j += ", \"training_windows\": " + std::to_string(nn->num_training_windows());
    }
    j += "},\n  \"fixed_part\": " + (fixed ? Json(r.fixed_part) : std::string("null")) + ",\n  " +
         FigureMembers(r.overall, fixed, eval.scorers, false) + ",\n  \"per_action\": {";
    bool first = true;
    for (size_t a = 0; a < ts.actions.size(); ++a) {
      if (r.per_action[a].windows == 0) continue;
      j += std::string(first ? "\n" : ",\n") + "    " + Json(ts.actions[a]) + ": {" +
           FigureMembers(r.per_action[a], fixed, eval.scorers) + "}";
      first = false;
    }
    j += "\n  },\n  \"seconds\": {\"total\": " + Num(seconds_total, "%.3f") +
         ", \"loading\": " + Num(seconds_loading, "%.3f") +
         ", \"test_windows_and_multimodal\": " + Num(seconds_multimodal, "%.3f") +
         ", \"predictor_setup\": " + Num(seconds_predictor_setup, "%.3f") +
         ", \"predictor\": " + Num(r.seconds_predicting, "%.3f") +
         ", \"metrics\": " + Num(r.seconds_metrics, "%.3f") +
         ", \"scorers\": " + Num(r.seconds_scoring, "%.3f") + "}\n}\n";
    WriteFileAtomically(o.json, j);
  }
}

}  // namespace

void AddEvalCommand(CLI::App& app, GlobalOptions& global) {
  auto o = std::make_shared<EvalCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "eval",
      "Evaluate a predictor on a protocol's test windows: APD, ADE, FDE, MMADE, MMFDE (metres, "
      "whole pose vectors, K samples per history), overall and per action.");
  cmd->add_option("--baseline", o->baseline,
                  "Non-learned predictor: zero-velocity (every sample repeats the last pose) or "
                  "nearest-neighbours (K training futures, stride-5 windows, re-targeted)");
  cmd->add_option("--model", o->model, "Trained model bundle folder (model.yaml + generator.pt)");
  cmd->add_option("--protocol", o->protocol, "Protocol name (bandai, h36m, humaneva) or YAML path")
      ->required();
  cmd->add_option("--data", o->data,
                  "The protocol's data folder: test clips of --split and the training clips")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--split", o->split, "Clips of --data to evaluate: test (default), train or all");
  cmd->add_option("--split-file", o->split_file, "Split file overriding the protocol's split.file");
  cmd->add_option("--clips", o->clips,
                  "Evaluate this folder of .bvh/.npy/.csv files instead (training clips still "
                  "come from --data)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("-k,--samples", o->k, "Samples per history (K, >= 2)");
  cmd->add_option("--seed", o->seed, "Seed (window i uses a mix of it and i)");
  cmd->add_option(
      "--constraints", o->constraints,
      "Constraint set for the angle-violation rate (default: the protocol's shipped set; "
      "'none' to skip)");
  cmd->add_option("--prior", o->prior,
                  "Prior bundle for the prior NLL (default: models/prior-<protocol> when shipped; "
                  "'none' to skip)");
  cmd->add_option("--fix", o->fix,
                  "Controllable setting: a part of the skeleton's default partition (e.g. legs) "
                  "that every sample shares; reports the APD of the varied and the fixed joints");
  cmd->add_flag(
      "--no-repair", o->no_repair,
      "With --model: score the network's raw futures, without moving poses that break the "
      "bundle's angle ranges back inside them");
  cmd->add_option("--json", o->json, "Also write every figure to this JSON file");
  cmd->callback([o, &global] { RunEval(*o, global); });
}

}  // namespace motionfork::app
