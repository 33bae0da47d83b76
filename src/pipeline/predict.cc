#include "pipeline/predict.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "bundle/dvae_bundle.h"
#include "bundle/generator_bundle.h"
#include "bundle/hgvae_bundle.h"
#include "config/rig_config.h"
#include "core/error.h"
#include "core/parallel_for.h"
#include "denoise/dvae_model.h"
#include "imputation/hgvae_model.h"
#include "pipeline/history_check.h"
#include "pipeline/history_repair.h"
#include "rig/joint_mapping.h"
#include "validity/pose_validator.h"

namespace motionfork::pipeline {
namespace {

// The first history frame: `start`, or the last t_his frames when it is -1. Throws FormatError
// naming the file when the motion is too short.
int HistoryStart(const HistoryInput& h, int t_his, double fps) {
  const int frames = h.motion.motion.num_frames();
  if (frames < t_his || (h.start >= 0 && h.start + t_his > frames)) {
    char need[160];
    std::snprintf(need, sizeof(need), "the model needs %d history frames (%.3g s at %.6g Hz)",
                  t_his, t_his / fps, fps);
    throw FormatError(h.name + ": " + need +
                      (h.start >= 0 ? ", frames " + std::to_string(h.start) + ".." +
                                          std::to_string(h.start + t_his - 1) + " with --start " +
                                          std::to_string(h.start)
                                    : std::string()) +
                      "; the motion has " + std::to_string(frames) + " frames");
  }
  return h.start >= 0 ? h.start : frames - t_his;
}

// Missing values in history frames [start, start + t_his).
int MissingInHistory(const MotionWithGaps& m, int start, int t_his) {
  const size_t fv = static_cast<size_t>(m.motion.num_joints()) * 3;
  return static_cast<int>(std::count(m.missing.begin() + start * fv,
                                     m.missing.begin() + (start + t_his) * fv, uint8_t{1}));
}

// Throws FormatError when the history frames have missing values and there is no imputer.
void RequireImputer(const std::string& name, int start, int t_his, int missing, bool imputer) {
  if (missing == 0 || imputer) return;
  throw FormatError(name + ": the history (frames " + std::to_string(start) + ".." +
                    std::to_string(start + t_his - 1) + ") has " + std::to_string(missing) +
                    " missing values; pass --impute DIR (an HG-VAE bundle, e.g. "
                    "models/bandai/hgvae) to fill them");
}

const std::string kWarning = "warning: ";

// The HG-VAE bundle that scores histories at the gate, or "".
std::string ScorerDir(const PredictFiles& files) {
  if (files.scorer_dir == "none") return "";
  if (!files.scorer_dir.empty()) return files.scorer_dir;
  if (!files.imputer_dir.empty()) return files.imputer_dir;
  const std::filesystem::path own = std::filesystem::path(files.model_dir) / "hgvae";
  return std::filesystem::is_regular_file(own / "hgvae.yaml") ? own.string() : "";
}

// The model's joints' roles under the shipped rig conventions; empty when none names them.
std::vector<std::string> ModelRoles(const Skeleton& skeleton, const std::string& config_dir) {
  try {
    return RolesOfSkeleton(skeleton, LoadRigConventions(config_dir)).roles;
  } catch (const std::invalid_argument&) {
    return {};
  }
}

}  // namespace

HistoryCheck GateHistory(const Forecaster& model, const PoseValidator& judge,
                         const HistoryGate& gate, const std::vector<std::string>& read_notes,
                         const std::vector<float>& history, const std::string& name, int start) {
  const Motion h(model.skeleton(), model.config().fps, history);
  HistoryCheck c = CheckHistory(h, judge.Score(history.data(), h.num_frames()), judge, gate.scorer,
                                gate.roles, gate.target_up);
  // Doubts raised while reading the file (turned over, sides exchanged) count too.
  for (const std::string& note : read_notes) {
    if (note.rfind(kWarning, 0) == 0)
      c.doubts.push_back(kReadingDoubt + note.substr(kWarning.size()));
  }
  if (gate.strict && !c.doubts.empty()) {
    std::string text;
    for (const std::string& d : c.doubts) text += "; " + d;
    throw FormatError(name + ": the history (frames " + std::to_string(start) + ".." +
                      std::to_string(start + h.num_frames() - 1) +
                      ") is far from what the model knows" + text + " (--strict: refused)");
  }
  return c;
}

HistoryGate GateForModel(const Forecaster& model, const std::string& config_dir,
                         const HgvaeModel* scorer, bool strict) {
  HistoryGate gate;
  gate.on = true;
  gate.scorer = scorer;
  gate.roles = ModelRoles(*model.skeleton(), config_dir);
  gate.target_up = ProtocolUp(config_dir, model.config().protocol);
  gate.strict = strict;
  return gate;
}

Prediction AssemblePrediction(const Forecaster& model, const std::string& model_dir,
                              const std::vector<float>& history, const std::vector<float>& futures,
                              const ForecastRequest& request, const PoseValidator& judge) {
  const ModelConfig& mc = model.config();
  const int J = model.skeleton()->num_joints();
  const size_t frame = static_cast<size_t>(J) * 3, future_size = mc.generator.t_pred * frame;
  if (history.size() != mc.generator.t_his * frame || futures.empty() ||
      futures.size() % future_size != 0) {
    throw std::invalid_argument("expected a history [" + std::to_string(mc.generator.t_his) + ", " +
                                std::to_string(J) + ", 3] and futures [K, " +
                                std::to_string(mc.generator.t_pred) + ", " + std::to_string(J) +
                                ", 3], got " + std::to_string(history.size()) + " and " +
                                std::to_string(futures.size()) + " values");
  }
  Prediction p;
  p.model = model_dir;
  p.protocol = mc.protocol;
  p.k = static_cast<int>(futures.size() / future_size);
  p.t_his = mc.generator.t_his;
  p.t_pred = mc.generator.t_pred;
  p.seed = request.seed;
  p.fps = mc.fps;
  p.prior_bound = judge.prior_bound();
  p.skeleton = model.skeleton();
  p.fixed_parts = request.fixed_parts;
  p.root_moves = model.moves_root();
  p.positions.reserve(static_cast<size_t>(p.k) * (history.size() + future_size));
  for (int k = 0; k < p.k; ++k) {
    p.positions.insert(p.positions.end(), history.begin(), history.end());
    p.positions.insert(p.positions.end(), futures.begin() + k * future_size,
                       futures.begin() + (k + 1) * future_size);
  }
  // Plausibility of every future (and of the history, for reference).
  if (judge.has_constraints() || judge.has_prior()) {
    p.history_validity = judge.Score(history.data(), p.t_his);
    for (int k = 0; k < p.k; ++k) {
      p.samples.push_back(judge.Score(futures.data() + k * future_size, p.t_pred));
    }
  }
  return p;
}

Prediction PredictFutures(const Forecaster& model, const std::string& model_dir,
                          const PoseValidator& validator, HistoryInput in,
                          const ForecastRequest& request, const HistoryRepair& repair,
                          const HistoryGate& gate) {
  const ModelConfig& mc = model.config();
  const int t_his = mc.generator.t_his;
  const int start = HistoryStart(in, t_his, mc.fps);
  Motion history = in.motion.motion;
  std::optional<HistoryImputation> imputation;
  if (const int missing = MissingInHistory(in.motion, start, t_his); missing > 0) {
    RequireImputer(in.name, start, t_his, missing, repair.imputer != nullptr);
    CheckImputerFits(*repair.imputer, repair.imputer_dir, model);
    imputation = ImputeHistory(*repair.imputer, repair.imputer_dir, in.name, start, t_his,
                               in.motion.missing, &history);
  }
  std::optional<HistoryDenoising> denoising;
  if (repair.denoiser) {
    denoising =
        DenoiseHistory(*repair.denoiser, repair.denoiser_dir, in.name, start, t_his, &history);
  }
  // The gate judges the (repaired) history before any forecast is made from it.
  std::optional<HistoryCheck> check;
  if (gate.on) {
    const size_t frame = static_cast<size_t>(history.num_joints()) * 3;
    const std::vector<float> frames(history.positions().begin() + start * frame,
                                    history.positions().begin() + (start + t_his) * frame);
    check = GateHistory(model, validator, gate, in.motion.notes, frames, in.name, start);
  }
  const Forecast f = model.Predict(history, start, request);

  Prediction p = AssemblePrediction(model, model_dir, f.history, f.futures, request, validator);
  p.history = in.name;
  p.start_frame = start;
  p.history_check = check;
  MarkFuturesOfDoubtedHistory(&p);
  p.imputation = imputation;
  p.denoising = denoising;
  return p;
}

Prediction PredictFromFiles(const PredictFiles& files, PredictNotes* notes) {
  Prediction out;
  PredictManyFromFiles(files, {files.history}, 1,
                       [&](int, const Prediction& p, const PredictNotes& n) {
                         out = p;
                         if (notes) *notes = n;
                       });
  return out;
}

void PredictManyFromFiles(const PredictFiles& files, const std::vector<std::string>& histories,
                          int threads, const PredictionDone& done) {
  ValidateForecastRequest(files.request);  // before any bundle is read
  Forecaster model = LoadForecaster(files.model_dir);
  model.SetPrecision(files.precision);
  const ModelConfig& mc = model.config();
  const int t_his = mc.generator.t_his;
  if (files.imputer_dir.empty() && !files.masks.empty())
    throw FormatError("--mask needs --impute (an HG-VAE bundle to fill the values)");
  std::vector<HistoryInput> inputs;
  bool missing_values = false;
  MotionInputOptions input = files.input;  // histories in the frame of the model's protocol
  input.target_up = ProtocolUp(input.config_dir, mc.protocol);
  for (const std::string& path : histories) {
    HistoryInput in;
    in.motion =
        LoadMotionWithGaps(path, input, model.skeleton(), mc.fps, files.masks, files.request.seed);
    in.name = path;
    in.start = files.start;
    const int start = HistoryStart(in, t_his, mc.fps);
    const int missing = MissingInHistory(in.motion, start, t_his);
    RequireImputer(path, start, t_his, missing, !files.imputer_dir.empty());
    missing_values = missing_values || missing > 0;
    inputs.push_back(std::move(in));
  }
  // The HG-VAE is loaded only when history frames have missing values or the gate scores with it.
  std::optional<HgvaeModel> imputer, scorer;
  std::optional<DvaeModel> denoiser;
  HistoryRepair repair;
  if (missing_values) {
    imputer.emplace(LoadHgvaeModel(files.imputer_dir));
    repair.imputer = &*imputer;
    repair.imputer_dir = files.imputer_dir;
  }
  HistoryGate gate;
  const std::string scorer_dir = files.gate ? ScorerDir(files) : "";
  std::string scorer_used;
  if (!scorer_dir.empty()) {
    if (scorer_dir == files.imputer_dir && imputer) {
      gate.scorer = &*imputer;
      scorer_used = scorer_dir;
    } else {
      try {
        scorer.emplace(LoadHgvaeModel(scorer_dir));
        CheckImputerFits(*scorer, scorer_dir, model);
        gate.scorer = &*scorer;
        scorer_used = scorer_dir;
      } catch (const std::exception&) {
        // The bundle's own HG-VAE does not fit its forecaster: the gate scores without it
        // (a given --impute DIR that does not fit is refused where it fills values).
        scorer.reset();
      }
    }
  }
  if (files.gate) gate = GateForModel(model, input.config_dir, gate.scorer, input.strict);
  if (!files.denoiser_dir.empty()) {
    denoiser.emplace(LoadDvaeModel(files.denoiser_dir));
    repair.denoiser = &*denoiser;
    repair.denoiser_dir = files.denoiser_dir;
  }
  const PoseValidator validator =
      PoseValidator::FromBundle(files.model_dir, model.skeleton(), mc.fps);
  PredictNotes notes;
  notes.angle_ranges = validator.has_constraints();
  notes.prior = validator.has_prior();
  // --strict with several files: every history as read (those without missing values) is judged
  // before any is forecast, so that a refusal leaves no file written.
  if (gate.on && gate.strict && inputs.size() > 1) {
    for (const HistoryInput& in : inputs) {
      const int start = HistoryStart(in, t_his, mc.fps);
      if (MissingInHistory(in.motion, start, t_his) > 0) continue;
      const size_t frame = static_cast<size_t>(in.motion.motion.num_joints()) * 3;
      const std::vector<float>& all = in.motion.motion.positions();
      GateHistory(
          model, validator, gate, in.motion.notes,
          std::vector<float>(all.begin() + start * frame, all.begin() + (start + t_his) * frame),
          in.name, start);
    }
  }
  notes.scorer = scorer_used;
  std::mutex lock;
  ParallelFor(static_cast<int>(inputs.size()), threads, [&](int i, int) {
    HistoryInput& in = inputs[static_cast<size_t>(i)];
    PredictNotes n = notes;
    n.resampled_from = in.motion.resampled_from;
    n.input = in.motion.notes;
    Prediction p = PredictFutures(model, files.model_dir, validator, std::move(in), files.request,
                                  repair, gate);
    p.reading = HistoryReading{std::filesystem::absolute(p.history).string(),
                               input.skeleton,
                               input.joint_map,
                               input.unit,
                               input.up,
                               input.left_right,
                               input.bvh_scale,
                               input.fps};
    std::lock_guard<std::mutex> guard(lock);
    done(i, p, n);
  });
}

ValiditySummary Summarise(const Prediction& p) {
  ValiditySummary s;
  double sum = 0;
  for (const SampleValidity& v : p.samples) {
    s.valid_futures += v.valid;
    s.failing_angles += v.violating_frames > 0;
    s.failing_prior += !v.prior_ok;
    s.failing_history += !v.history_ok;
    sum += v.prior_nll.value_or(0.0);
  }
  if (!p.samples.empty()) s.mean_prior_nll = sum / p.samples.size();
  return s;
}

}  // namespace motionfork::pipeline
