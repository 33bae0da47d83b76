#include "generator/training/eval_experiment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bundle/generator_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/protocol_dataset.h"
#include "config/rig_config.h"
#include "config/skeleton_config.h"
#include "core/heading.h"
#include "eval/baselines.h"
#include "eval/clip_folder.h"
#include "eval/test_set.h"
#include "generator/inference/forecaster.h"
#include "generator/training/generator_predictor.h"
#include "rig/body_frame.h"
#include "rig/joint_mapping.h"
#include "torch_util/threads.h"
#include "validity/pose_validator.h"

namespace motionfork {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

const char* const kBaselines = "zero-velocity, constant-velocity, nearest-neighbours";
const char* const kNeedsData =
    "--baseline nearest-neighbours needs --data DIR: its training clips are the protocol's train "
    "split";

bool IsNearestNeighbours(const EvalExperimentOptions& o) {
  return !o.baseline.empty() && CanonicalBaseline(o.baseline) == "nearest-neighbours";
}

void Validate(const EvalExperimentOptions& o) {
  if (o.baseline.empty() == o.model.empty()) {
    throw std::invalid_argument("give one of --baseline NAME (" + std::string(kBaselines) +
                                ") or --model DIR");
  }
  if (o.k < 2) {
    throw std::invalid_argument(
        "-k: expected K >= 2 samples per history (APD is a mean over pairs of samples), got " +
        std::to_string(o.k));
  }
  if (o.subset != "test" && o.subset != "train" && o.subset != "all") {
    throw std::invalid_argument("--subset: expected test, train or all, got '" + o.subset + "'");
  }
  if (o.data.empty() && o.clips.empty()) {
    throw std::invalid_argument("give --data DIR (the protocol's dataset) and/or --clips DIR");
  }
  if (!std::isfinite(o.turn_degrees)) {
    throw std::invalid_argument("--turn: expected degrees, got " + std::to_string(o.turn_degrees));
  }
  if (!o.model.empty()) LoadForecaster(o.model);  // fail before loading anything
  if (IsNearestNeighbours(o) && o.data.empty()) throw std::invalid_argument(kNeedsData);
  if (!o.split_file.empty() && !fs::is_regular_file(o.split_file)) {
    throw std::invalid_argument("--split: '" + o.split_file + "' is not a file");
  }
}

int FixedPart(const std::string& fix, const Skeleton& skeleton) {
  if (fix.empty()) return -1;
  const Partition& partition = skeleton.GetPartition();
  std::string names;
  for (size_t i = 0; i < partition.parts.size(); ++i) {
    if (partition.parts[i].name == fix) return static_cast<int>(i);
    names += (i ? ", " : "") + partition.parts[i].name;
  }
  throw std::invalid_argument("--fix: skeleton '" + skeleton.name() + "' has no part '" + fix +
                              "' in its default partition '" + partition.name +
                              "'; expected one of " + names);
}

void CheckProtocolSplitFile(const EvalExperimentOptions& o, const ProtocolOptions& protocol) {
  if (o.data.empty() || !o.split_file.empty() || protocol.split_file.empty()) return;
  fs::path split = protocol.split_file;
  if (split.is_relative()) split = fs::path(o.data) / split;
  if (!fs::is_regular_file(split)) {
    throw std::invalid_argument("split file '" + split.string() + "' not found (protocol '" +
                                protocol.name +
                                "' expects it in the data folder; pass --split FILE otherwise)");
  }
}

// Plausibility scorers: angle-violation rate (any constraint outside its range in a frame) and
// prior NLL (nats per pose); each optional.
std::vector<FrameScorer> MakeScorers(const EvalExperimentOptions& o, const ProtocolOptions& p,
                                     const std::shared_ptr<const Skeleton>& skeleton,
                                     std::unique_ptr<PoseValidator>* validator) {
  std::string constraints = o.constraints;
  if (constraints.empty() &&
      fs::is_regular_file(fs::path(o.config_dir) / "constraints" / (p.name + ".yaml"))) {
    constraints = p.name;
  }
  const std::string constraints_path =
      !constraints.empty() && constraints != "none"
          ? ResolveConfigPath(o.config_dir, "constraints", constraints)
          : "";
  std::string prior = o.prior;
  const fs::path shipped = fs::path(o.models_dir) / ("prior-" + p.name);
  if (prior.empty() && !o.models_dir.empty() && fs::is_directory(shipped)) {
    prior = shipped.string();
  }
  if (prior == "none") prior.clear();
  *validator = std::make_unique<PoseValidator>(skeleton, p.fps, constraints_path, prior);
  const PoseValidator* v = validator->get();
  auto copy = [](const std::vector<double>& from, double* to) {
    std::copy(from.begin(), from.end(), to);
  };
  std::vector<FrameScorer> scorers;
  if (v->has_constraints()) {
    scorers.push_back({"angle_violation_rate", [v, copy](const float* pos, int n, double* s) {
                         copy(v->ViolationFlags(pos, n), s);
                       }});
  }
  if (v->has_prior()) {
    scorers.push_back({"prior_nll", [v, copy](const float* pos, int n, double* s) {
                         copy(v->PriorNll(pos, n), s);
                       }});
  }
  return scorers;
}

// The predictor the options ask for. training: the protocol's training clips (for the
// nearest-neighbour baseline); they outlive the predictor.
std::unique_ptr<Predictor> MakePredictor(const EvalExperimentOptions& o, const ProtocolOptions& p,
                                         const std::shared_ptr<const Skeleton>& skeleton,
                                         const std::vector<const Motion*>& training) {
  if (!o.model.empty()) {
    Forecaster f = LoadForecaster(o.model);
    f.SetPrecision(o.precision);
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
                                                o.repair);
  }
  if (CanonicalBaseline(o.baseline) == "zero-velocity") {
    return std::make_unique<ZeroVelocityPredictor>(skeleton, p.t_his, p.t_pred);
  }
  if (CanonicalBaseline(o.baseline) == "constant-velocity") {
    if (p.up.empty()) {
      throw std::invalid_argument("--baseline constant-velocity needs the protocol's up axis: '" +
                                  p.name + "' declares none (up: in its YAML)");
    }
    const auto [axis, sign] = ParseUpAxis(p.up);
    return std::make_unique<ConstantVelocityPredictor>(skeleton, p.t_his, p.t_pred,
                                                       UpAxis{axis, sign}, o.velocity);
  }
  if (o.data.empty()) throw std::invalid_argument(kNeedsData);
  if (training.empty()) {
    throw std::invalid_argument(
        "--baseline nearest-neighbours needs training clips: the train split of " + o.data +
        " has no clip of at least " + std::to_string(p.window_length()) + " frames");
  }
  NearestNeighbourOptions nn;  // the definition: stride 5; include_last as SlidingWindows
  return std::make_unique<NearestNeighbourPredictor>(training, p.t_his, p.t_pred, nn);
}

// The clips evaluated and where they come from; throws when there are none.
struct TestClips {
  Dataset dataset;  // --data (training clips; test clips unless --clips)
  ClipFolder folder;
  std::vector<const Clip*> test;
  std::vector<Clip> turned;  // --turn: copies of the test clips, turned
  std::string source;
};

// Turns every test clip by `degrees` about the protocol's up axis (copies; the test pointers
// move to them).
void TurnTestClips(double degrees, const ProtocolOptions& protocol, TestClips* clips) {
  if (protocol.up.empty()) {
    throw std::invalid_argument("--turn: protocol '" + protocol.name +
                                "' declares no up axis to turn the clips about");
  }
  const auto [axis, sign] = ParseUpAxis(protocol.up);
  clips->turned.reserve(clips->test.size());
  for (const Clip*& c : clips->test) {
    Clip turned = *c;
    Motion& m = turned.motion;
    RotateAboutUp(m.mutable_frame(0), static_cast<size_t>(m.num_frames()) * m.num_joints(),
                  degrees * M_PI / 180.0, UpAxis{axis, sign});
    clips->turned.push_back(std::move(turned));
    c = &clips->turned.back();
  }
  std::ostringstream turn;
  turn << ", turned " << degrees << " degrees about " << protocol.up;
  clips->source += turn.str();
}

void LoadTestClips(const EvalExperimentOptions& o, const ProtocolOptions& protocol,
                   const SkeletonConfig& skeleton, TestClips* out) {
  auto relay = [&o](const std::string& stage) {
    return [&o, stage](const LoadProgress& p) {
      ReportProgress(o.progress, stage, p.fraction, p.detail);
    };
  };
  if (!o.data.empty()) {
    out->dataset = LoadDataset(
        protocol, skeleton, o.data,
        ReportingLoadOptions(o.cache_dir, o.split_file, o.progress, "loading " + protocol.name));
  }
  if (!o.clips.empty()) {
    ClipFolderOptions read;
    read.progress = relay("reading clips");
    read.conform = o.conform_clips;
    out->folder = LoadClipFolder(protocol, skeleton, o.clips, read);
    for (const std::string& w : out->folder.warnings) ReportWarning(o.progress, w);
    for (const Clip& c : out->folder.clips) out->test.push_back(&c);
    out->source = o.clips;
  } else {
    for (const Clip& c : out->dataset.clips) {
      if (o.subset == "all" || (o.subset == "test") == (c.split == Split::kTest)) {
        out->test.push_back(&c);
      }
    }
    out->source = "split '" + o.subset + "' of " + o.data;
  }
  if (!out->test.empty()) return;
  int listed = 0;
  for (const SkippedClip& c : o.clips.empty() ? out->dataset.skipped : out->folder.skipped) {
    listed += !o.clips.empty() || o.subset == "all" || c.split == o.subset;
  }
  const int min_length = protocol.min_length > 0 ? protocol.min_length : protocol.window_length();
  throw std::invalid_argument("nothing to evaluate: " + out->source +
                              (listed == 0
                                   ? std::string(" holds no clips (check the split file)")
                                   : " holds " + std::to_string(listed) + " clips, none of the " +
                                         std::to_string(min_length) + " frames protocol '" +
                                         protocol.name + "' needs"));
}

// Where the body goes: on when the protocol declares its up axis; skating needs the ankles, found
// by the rig convention that names the skeleton's joints (configs/rigs/), else left out.
RootOptions MakeRootOptions(const ProtocolOptions& p, const Skeleton& skeleton,
                            const std::string& config_dir, std::string* feet_described) {
  RootOptions root;
  if (p.up.empty()) return root;
  const auto [axis, sign] = ParseUpAxis(p.up);
  root.enabled = true;
  root.up = {axis, sign};
  root.feet = AnkleJoints(skeleton, config_dir);
  for (int j : root.feet)
    *feet_described += (feet_described->empty() ? "" : ", ") + skeleton.joint_name(j);
  return root;
}

}  // namespace

std::vector<std::string> DifferencesFromPublished(const EvalExperimentOptions& o,
                                                  const EvalExperiment& x) {
  std::vector<std::string> out;
  if (o.k != 50) out.push_back("K = " + std::to_string(o.k));
  if (!x.result.fixed_part.empty()) out.push_back("a fixed part");
  if (!o.clips.empty()) out.push_back("a clips folder");
  if (o.turn_degrees != 0) out.push_back("turned clips");
  if (o.subset != "test") out.push_back("the '" + o.subset + "' clips");
  if (!o.split_file.empty()) out.push_back("another split file");
  return out;
}

std::vector<std::string> FiguresLeading(const Figures& ours, const PublishedFigures& p) {
  std::vector<std::string> out;
  if (ours.apd > p.apd) out.push_back("APD");
  if (ours.ade < p.ade) out.push_back("ADE");
  if (ours.fde < p.fde) out.push_back("FDE");
  if (ours.mmade < p.mmade) out.push_back("MMADE");
  if (ours.mmfde < p.mmfde) out.push_back("MMFDE");
  return out;
}

std::string CanonicalBaseline(const std::string& name) {
  if (name == "zero-velocity" || name == "zero") return "zero-velocity";
  if (name == "constant-velocity" || name == "cv") return "constant-velocity";
  if (name == "nearest-neighbours" || name == "nearest-neighbors" || name == "nn") {
    return "nearest-neighbours";
  }
  throw std::invalid_argument("--baseline: unknown baseline '" + name + "'; expected one of " +
                              kBaselines);
}

EvalExperiment RunEvalExperiment(const EvalExperimentOptions& o) {
  const auto start_all = Clock::now();
  Validate(o);
  EvalExperiment x;
  x.protocol = LoadProtocolConfig(ResolveConfigPath(o.config_dir, "protocols", o.protocol));
  const ProtocolOptions& protocol = x.protocol;
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(o.config_dir, "skeletons", protocol.skeleton));
  EvalOptions eval;
  eval.fixed_part = FixedPart(o.fix, *skeleton.skeleton);
  CheckProtocolSplitFile(o, protocol);

  auto start = Clock::now();
  TestClips clips;
  LoadTestClips(o, protocol, skeleton, &clips);
  if (o.turn_degrees != 0) TurnTestClips(o.turn_degrees, protocol, &clips);
  std::vector<const Motion*> training;
  for (const Clip& c : clips.dataset.clips) {
    if (c.split == Split::kTrain) training.push_back(&c.motion);
  }
  x.test_source = clips.source;
  x.seconds_loading = Since(start);

  start = Clock::now();
  TestSet ts = BuildTestSet(clips.test, protocol);
  x.multimodal_cached =
      AttachMultimodalSets(&ts, protocol.multimodal_threshold, o.cache_dir, protocol.name);
  x.seconds_multimodal = Since(start);

  start = Clock::now();
  std::unique_ptr<Predictor> predictor = MakePredictor(o, protocol, ts.skeleton, training);
  x.seconds_predictor_setup = Since(start);

  eval.num_samples = o.k;
  eval.seed = o.seed;
  eval.threads = WindowThreads(o.threads);  // each single-threaded: the same sums for any count
  eval.keep_singleton_sets = protocol.keep_singleton_sets;
  std::unique_ptr<PoseValidator> validator;
  eval.scorers = MakeScorers(o, protocol, ts.skeleton, &validator);
  eval.root = MakeRootOptions(protocol, *ts.skeleton, o.config_dir, &x.feet);
  x.root_figures = eval.root.enabled;
  const std::string stage = "evaluating " + predictor->name();
  eval.progress = [&o, &stage](int done, int total) {
    ReportProgress(o.progress, stage, double(done) / total);
  };
  x.result = Evaluate(*predictor, ts, eval);
  x.seconds_total = Since(start_all);

  std::set<int> clips_used;
  for (const Window& w : ts.windows) clips_used.insert(w.clip);
  x.windows = ts.num_windows();
  x.clips = static_cast<int>(clips_used.size());
  x.pose_dims = ts.pose_dims;
  x.actions = ts.actions;
  x.predictor_name = predictor->name();
  x.predictor_description = predictor->description();
  x.bundle_hash = predictor->bundle_hash();
  x.learned = !o.model.empty();
  if (const auto* nn = dynamic_cast<const NearestNeighbourPredictor*>(predictor.get())) {
    x.training_windows = nn->num_training_windows();
  }
  x.overlaps_training = o.subset != "test" && o.clips.empty() && IsNearestNeighbours(o);
  x.scorers_described = validator->described();
  for (const FrameScorer& s : eval.scorers) x.scorer_names.push_back(s.name);
  return x;
}

}  // namespace motionfork
