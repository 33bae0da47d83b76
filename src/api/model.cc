// motionfork::Model (include/motionfork/motionfork.h) on top of the pipeline library (forecast,
// judge, write), the angle checker and the motion readers: this file only adapts types and finds
// configs.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "bundle/generator_bundle.h"
#include "bundle/hgvae_bundle.h"
#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "config_dir.h"
#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "core/error.h"
#include "core/resample.h"
#include "generator/inference/forecaster.h"
#include "imputation/hgvae_model.h"
#include "io/motion_file.h"
#include "io/prediction_file.h"
#include "motionfork/motionfork.h"
#include "pipeline/export.h"
#include "pipeline/history_check.h"
#include "pipeline/history_repair.h"
#include "pipeline/motion_input.h"
#include "pipeline/predict.h"
#include "positions.h"
#include "torch_util/threads.h"
#include "validity/pose_validator.h"

namespace motionfork {
namespace {

namespace fs = std::filesystem;

// The constraint config file for a bundle, or "" for none: the option (must resolve), else the
// bundle's own (DIR/constraints.yaml, copied there by training), else the shipped set named like
// its protocol when there is one.
std::string FindConstraintFile(const std::string& option, const std::string& protocol,
                               const std::string& config_dir, const std::string& bundle_dir) {
  if (option == "none") return "";
  if (option.empty()) {
    const fs::path own = fs::path(bundle_dir) / "constraints.yaml";
    if (fs::is_regular_file(own)) return own.string();
    const fs::path shipped = fs::path(config_dir) / "constraints" / (protocol + ".yaml");
    return !config_dir.empty() && fs::is_regular_file(shipped) ? shipped.string() : "";
  }
  if (config_dir.empty() && !fs::is_regular_file(option)) {
    throw FormatError("LoadOptions::constraints '" + option +
                      "': not a file, and no configs folder was found to look it up by name; set "
                      "$MOTIONFORK_CONFIG_DIR or LoadOptions::config_dir");
  }
  return ResolveConfigPath(config_dir, "constraints", option);
}

SampleCheck ToSampleCheck(const ConstraintSet& set, const CheckResult& r) {
  SampleCheck out;
  std::vector<bool> violated(r.num_constraints, false);
  for (int t = 0; t < r.num_frames; ++t) {
    bool outside = false, undefined = false;
    for (int c = 0; c < r.num_constraints; ++c) {
      const AngleStatus s = r.at(t, c);
      if (IsViolation(s)) outside = violated[c] = true;
      if (s == AngleStatus::kDegenerate) undefined = true;
    }
    if (outside) out.violating_frames.push_back(t);
    if (undefined) out.undefined_frames.push_back(t);
  }
  for (int c = 0; c < r.num_constraints; ++c) {
    if (violated[c]) out.violated_constraints.push_back(set.constraint(c).name);
  }
  out.valid = out.violating_frames.empty() && out.undefined_frames.empty();
  return out;
}

}  // namespace

std::string FindConfigDir(const std::string& given) {
  std::string chosen = given, what = "LoadOptions::config_dir";
  if (chosen.empty()) {
    if (const char* env = std::getenv("MOTIONFORK_CONFIG_DIR"); env && *env) {
      chosen = env;
      what = "$MOTIONFORK_CONFIG_DIR";
    }
  }
  if (!chosen.empty()) {
    if (!fs::is_directory(chosen)) {
      throw std::invalid_argument(what +
                                  ": expected the configs folder (holding constraints/, "
                                  "skeletons/, ...), got '" +
                                  chosen + "', which is not a folder");
    }
    return chosen;
  }
  for (const char* dir : {MOTIONFORK_INSTALLED_CONFIG_DIR, MOTIONFORK_SOURCE_CONFIG_DIR}) {
    if (*dir && fs::is_directory(dir)) return dir;
  }
  return "";
}

struct Model::Impl {
  Impl(Forecaster f, const std::string& dir)
      : forecaster(std::move(f)),
        bundle_dir(dir),
        bundle_judge(
            PoseValidator::FromBundle(dir, forecaster.skeleton(), forecaster.config().fps)),
        no_judge(forecaster.skeleton(), forecaster.config().fps, "", "") {}

  Forecaster forecaster;
  std::string bundle_dir;
  PoseValidator bundle_judge;  // the bundle's own constraints and prior (prediction files)
  PoseValidator no_judge;      // Predict() leaves judging to Check()
  std::vector<Part> parts;
  std::string config_dir, constraint_name, constraint_file;
  // How ReadMotion() and Conform() put a motion on the model (LoadOptions' joint map and frame,
  // the protocol's up axis), set once at Load.
  pipeline::MotionInputOptions read_as;
  std::optional<ConstraintSet> constraints;

  const Skeleton& skeleton() const { return *forecaster.skeleton(); }

  // read_scale: metres per file unit the values were read with (rig/body_frame.h).
  std::vector<float> OnModel(const Motion& m, std::vector<std::string>* notes,
                             double read_scale = 1.0) const;

  // positions: [T, J, 3] on the model's joints as a Motion (checks the size and finiteness,
  // naming the frame and joint of a bad value).
  Motion ToMotion(const std::vector<float>& positions, const char* who) const {
    return MotionFromPositions(forecaster.skeleton(), forecaster.config().fps, positions, who);
  }

  // The bundle's HG-VAE (BUNDLE/hgvae), loaded at the first CheckHistory; null when there is none
  // or it does not fit the forecaster.
  const HgvaeModel* Scorer() const {
    std::call_once(scorer_loaded, [&] {
      const fs::path dir = fs::path(bundle_dir) / "hgvae";
      if (!fs::is_regular_file(dir / "hgvae.yaml")) return;
      try {
        scorer.emplace(LoadHgvaeModel(dir.string()));
        pipeline::CheckImputerFits(*scorer, dir.string(), forecaster);
      } catch (const std::exception&) {
        scorer.reset();  // one that does not fit its forecaster: the gate scores without it
      }
    });
    return scorer ? &*scorer : nullptr;
  }
  mutable std::once_flag scorer_loaded;
  mutable std::optional<HgvaeModel> scorer;

  SampleCheck CheckFrames(const Motion& motion) const {
    if (!constraints) {
      throw std::logic_error(
          "Check: the model has no constraint set (its bundle holds no constraints.yaml, none is "
          "shipped for its protocol '" +
          forecaster.config().protocol +
          "', or LoadOptions::constraints was \"none\"); name one in LoadOptions::constraints");
    }
    SampleCheck out = ToSampleCheck(*constraints, motionfork::Check(*constraints, motion));
    if (bundle_judge.has_prior()) {
      const SampleValidity v = bundle_judge.Score(motion.positions().data(), motion.num_frames());
      out.prior_nll = v.prior_nll.value_or(std::numeric_limits<double>::quiet_NaN());
      out.prior_ok = v.prior_ok;
    }
    if (!out.violating_frames.empty() || !out.undefined_frames.empty())
      out.failed.push_back("angle_ranges");
    if (!out.prior_ok) out.failed.push_back("prior_nll");
    out.valid = out.failed.empty();
    return out;
  }
};

Model::Model(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;

Model Model::Load(const std::string& bundle_dir, const LoadOptions& options) {
  if (options.threads < 0) {
    throw std::invalid_argument("LoadOptions::threads: expected >= 0 (0 = leave as is), got " +
                                std::to_string(options.threads));
  }
  if (options.threads > 0) PinThreads(options.threads);
  const Precision precision = ParsePrecision(options.precision);  // before loading anything
  auto impl = std::make_unique<Impl>(LoadForecaster(bundle_dir), bundle_dir);
  impl->forecaster.SetPrecision(precision);
  const Skeleton& skeleton = impl->skeleton();
  const PartPlan& plan = impl->forecaster.parts();
  for (int p = 0; p < plan.num_parts(); ++p) {
    Part part{plan.names[p], {}};
    for (int64_t node : plan.nodes[p]) part.joints.push_back(skeleton.joint_name(node + 1));
    impl->parts.push_back(std::move(part));
  }
  impl->config_dir = FindConfigDir(options.config_dir);
  impl->read_as.config_dir = impl->config_dir;
  impl->read_as.joint_map = options.joint_map;
  impl->read_as.unit = options.unit;
  impl->read_as.up = options.up;
  impl->read_as.left_right = options.left_right;
  impl->read_as.target_up =
      pipeline::ProtocolUp(impl->config_dir, impl->forecaster.config().protocol);
  impl->constraint_file = FindConstraintFile(
      options.constraints, impl->forecaster.config().protocol, impl->config_dir, bundle_dir);
  if (!impl->constraint_file.empty()) {
    impl->constraints = ConstraintSet::Build(LoadConstraintConfig(impl->constraint_file), skeleton);
    impl->constraint_name = impl->constraints->name();
  }
  return Model(std::move(impl));
}

const std::vector<std::string>& Model::joint_names() const {
  return impl_->skeleton().joint_names();
}
const std::vector<int>& Model::parents() const { return impl_->skeleton().parents(); }
const std::vector<std::pair<int, int>>& Model::left_right_pairs() const {
  return impl_->skeleton().left_right_pairs();
}
const std::vector<Part>& Model::parts() const { return impl_->parts; }
int Model::history_frames() const { return impl_->forecaster.config().generator.t_his; }
int Model::future_frames() const { return impl_->forecaster.config().generator.t_pred; }
double Model::fps() const { return impl_->forecaster.config().fps; }
const std::string& Model::protocol() const { return impl_->forecaster.config().protocol; }
const std::string& Model::constraint_set() const { return impl_->constraint_name; }
const std::string& Model::constraint_file() const { return impl_->constraint_file; }
const std::string& Model::config_dir() const { return impl_->config_dir; }

Futures Model::Predict(const std::vector<float>& history, const PredictOptions& options) const {
  const Motion motion = impl_->ToMotion(history, "Predict: history");
  if (motion.num_frames() < history_frames()) {
    throw std::invalid_argument(
        "Predict: expected a history of at least " + std::to_string(history_frames()) +
        " frames (" + std::to_string(history_frames() / fps()) + " s at " + std::to_string(fps()) +
        " Hz), got " + std::to_string(motion.num_frames()));
  }
  const ForecastRequest request{options.k, options.seed, options.fixed_parts, options.repair};
  pipeline::HistoryInput in;
  in.motion.motion = motion;
  in.motion.missing.assign(motion.positions().size(), 0);
  in.name = "Predict: history";
  const Prediction p = pipeline::PredictFutures(impl_->forecaster, impl_->bundle_dir,
                                                impl_->no_judge, std::move(in), request);
  Futures out;
  out.k = p.k;
  out.frames = p.t_pred;
  out.joints = p.joints();
  out.fps = p.fps;
  out.history_frames = p.t_his;
  out.root_moves = p.root_moves;
  const size_t frame = static_cast<size_t>(p.joints()) * 3;
  out.history.assign(p.positions.begin(), p.positions.begin() + p.t_his * frame);
  out.positions.reserve(static_cast<size_t>(p.k) * p.t_pred * frame);
  for (int k = 0; k < p.k; ++k) {
    const float* future = p.sample(k) + p.t_his * frame;
    out.positions.insert(out.positions.end(), future, future + p.t_pred * frame);
  }
  return out;
}

std::vector<SampleCheck> Model::Check(const Futures& futures) const {
  const int J = static_cast<int>(joint_names().size());
  const size_t per_sample = static_cast<size_t>(futures.frames) * J * 3;
  if (futures.joints != J || futures.k < 1 || futures.frames < 1 ||
      futures.positions.size() != futures.k * per_sample) {
    throw std::invalid_argument("Check: expected futures [k, frames, " + std::to_string(J) +
                                ", 3] holding k * frames * " + std::to_string(J * 3) +
                                " values, got k = " + std::to_string(futures.k) +
                                ", frames = " + std::to_string(futures.frames) +
                                ", joints = " + std::to_string(futures.joints) + " and " +
                                std::to_string(futures.positions.size()) + " values");
  }
  std::vector<SampleCheck> out;
  for (int i = 0; i < futures.k; ++i) {
    const float* s = futures.sample(i);
    out.push_back(impl_->CheckFrames(
        impl_->ToMotion(std::vector<float>(s, s + per_sample), "Check: futures")));
  }
  return out;
}

SampleCheck Model::CheckMotion(const std::vector<float>& positions) const {
  return impl_->CheckFrames(impl_->ToMotion(positions, "CheckMotion: positions"));
}

HistoryDoubts Model::CheckHistory(const std::vector<float>& history) const {
  const Motion motion = impl_->ToMotion(history, "CheckHistory: history");
  if (motion.num_frames() < history_frames()) {
    throw std::invalid_argument("CheckHistory: expected a history of at least " +
                                std::to_string(history_frames()) + " frames, got " +
                                std::to_string(motion.num_frames()));
  }
  const Motion last = motion.Slice(motion.num_frames() - history_frames(), motion.num_frames());
  const PoseValidator& judge = impl_->bundle_judge;
  const pipeline::HistoryGate gate =
      pipeline::GateForModel(impl_->forecaster, impl_->config_dir, impl_->Scorer(), false);
  const HistoryCheck c =
      pipeline::CheckHistory(last, judge.Score(last.positions().data(), last.num_frames()), judge,
                             gate.scorer, gate.roles, gate.target_up);
  HistoryDoubts out;
  out.window_score = c.window_score.value_or(out.window_score);
  out.window_bound = c.window_bound.value_or(out.window_bound);
  out.doubts = c.doubts;
  return out;
}

// `m` on the model's joints (by name, else by the roles of its rig) at its frame rate.
std::vector<float> Model::Impl::OnModel(const Motion& m, std::vector<std::string>* notes,
                                        double read_scale) const {
  SkeletonConfig onto;
  onto.skeleton = onto.source = forecaster.skeleton();
  pipeline::ConformedMotion c = pipeline::ConformForModel(m, {}, onto, read_as, read_scale);
  if (notes) *notes = std::move(c.notes);
  const double fps = forecaster.config().fps;
  if (std::abs(c.motion.fps() - fps) > 1e-6 * fps) c.motion = Resample(c.motion, fps);
  return c.motion.positions();
}

std::vector<float> Model::ReadMotion(const std::string& path,
                                     std::vector<std::string>* notes) const {
  MotionReadOptions read;
  read.skeleton = impl_->forecaster.skeleton();  // names .npy joints, maps .csv columns
  read.fps = fps();                              // for files that store no frame rate
  const Motion m = ReadMotionFile(path, read);
  try {
    return impl_->OnModel(
        m, notes, FormatOfPath(path) == MotionFormat::kBvh ? read.bvh.scale_to_metres : 1.0);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
}

std::vector<float> Model::Conform(const MotionData& motion, std::vector<std::string>* notes) const {
  return impl_->OnModel(MotionFromPositions(motion.joint_names, motion.parents, motion.fps,
                                            motion.positions, "Conform: motion"),
                        notes);
}

}  // namespace motionfork

namespace motionfork {

const char* Version() { return MOTIONFORK_VERSION_STRING; }

std::vector<float> Futures::Sequence(int i) const {
  if (i < 0 || i >= k) {
    throw std::invalid_argument("Futures::Sequence: expected a sample in [0, " + std::to_string(k) +
                                "), got " + std::to_string(i));
  }
  std::vector<float> out(history);
  out.insert(out.end(), sample(i), sample(i) + static_cast<size_t>(frames) * joints * 3);
  return out;
}

bool Model::has_prior() const { return impl_->bundle_judge.has_prior(); }

double Model::prior_bound() const {
  return impl_->bundle_judge.prior_bound().value_or(std::numeric_limits<double>::quiet_NaN());
}

std::vector<double> Model::PriorNll(const std::vector<float>& positions) const {
  if (!has_prior()) {
    throw std::logic_error("PriorNll: the bundle '" + impl_->bundle_dir +
                           "' carries no pose prior (prior/)");
  }
  const Motion m = impl_->ToMotion(positions, "PriorNll: positions");
  return impl_->bundle_judge.PriorNll(m.positions().data(), m.num_frames());
}

double Model::MeanPriorNll(const std::vector<float>& positions) const {
  const std::vector<double> nll = PriorNll(positions);
  double mean = 0;
  for (double v : nll) mean += v / static_cast<double>(nll.size());
  return mean;
}

namespace {

// The prediction-file form of futures (history then each future), judged by `judge`.
Prediction ToPrediction(const Futures& f, const Forecaster& forecaster, const std::string& model,
                        const PoseValidator& judge, const PredictOptions& options) {
  const int J = forecaster.skeleton()->num_joints();
  if (f.joints != J || f.k < 1 || f.frames != forecaster.config().generator.t_pred ||
      f.history_frames != forecaster.config().generator.t_his ||
      f.positions.size() != static_cast<size_t>(f.k) * f.frames * J * 3 ||
      f.history.size() != static_cast<size_t>(f.history_frames) * J * 3) {
    throw std::invalid_argument(
        "WritePrediction: expected futures from Model::Predict ([k, frames, " + std::to_string(J) +
        ", 3] positions and [history_frames, " + std::to_string(J) +
        ", 3] history), got k = " + std::to_string(f.k) + ", frames = " + std::to_string(f.frames) +
        ", history_frames = " + std::to_string(f.history_frames) +
        ", joints = " + std::to_string(f.joints));
  }
  ForecastRequest request;
  request.seed = options.seed;
  request.fixed_parts = options.fixed_parts;
  return pipeline::AssemblePrediction(forecaster, model, f.history, f.positions, request, judge);
}

}  // namespace

std::string Model::WritePrediction(const std::string& out, const Futures& futures,
                                   const PredictOptions& options) const {
  Prediction p =
      ToPrediction(futures, impl_->forecaster, impl_->bundle_dir, impl_->bundle_judge, options);
  // The history's doubts and the futures' validity as `motionfork predict` writes them.
  p.history_check = pipeline::GateHistory(
      impl_->forecaster, impl_->bundle_judge,
      pipeline::GateForModel(impl_->forecaster, impl_->config_dir, impl_->Scorer(), false), {},
      futures.history, out, 0);
  pipeline::MarkFuturesOfDoubtedHistory(&p);
  return motionfork::WritePrediction(out, p);
}

std::vector<std::string> Model::ExportBvh(const std::string& out, const Futures& futures,
                                          const BvhExportOptions& options) const {
  if (out.size() < 4 || out.compare(out.size() - 4, 4, ".bvh") != 0) {
    throw std::invalid_argument("ExportBvh: expected a path ending in .bvh, got '" + out + "'");
  }
  BvhWriteOptions bvh;
  bvh.scale_to_metres = options.scale;
  bvh.rotation_order = options.rotation_order;
  bvh.fit.lengths = options.exact_lengths ? BoneLengths::kExact : BoneLengths::kMean;
  ValidateBvhWriteOptions(bvh);
  const Prediction p =
      ToPrediction(futures, impl_->forecaster, impl_->bundle_dir, impl_->no_judge, {});
  std::vector<std::string> paths;
  for (const pipeline::WrittenSample& w :
       pipeline::ExportPrediction(p, "ExportBvh", out, options.sample, bvh)) {
    paths.push_back(w.path);
  }
  return paths;
}

}  // namespace motionfork
