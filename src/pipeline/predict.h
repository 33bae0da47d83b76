// The forecasting pipeline: read a history -> repair it (impute, denoise) -> forecast K futures ->
// judge every future (angle ranges, prior NLL). What `motionfork predict` and the C++ API run;
// the result is the prediction file's content (io/prediction_file.h), written by the caller.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "generator/inference/forecaster.h"
#include "io/prediction_file.h"
#include "pipeline/motion_input.h"

namespace motionfork {
class DvaeModel;
class HgvaeModel;
class PoseValidator;
}  // namespace motionfork

namespace motionfork::pipeline {

// What repairs a history before forecasting; each may be null (that step is off).
struct HistoryRepair {
  const HgvaeModel* imputer = nullptr;  // fills missing values (required when there are some)
  std::string imputer_dir;              // its bundle, named in errors and in the result
  const DvaeModel* denoiser = nullptr;  // denoises the history (after any imputation)
  std::string denoiser_dir;
};

// The plausibility gate before forecasting (pipeline/history_check.h); off unless `on`.
struct HistoryGate {
  bool on = false;
  const HgvaeModel* scorer = nullptr;  // its window score judges the history too (may be null)
  std::vector<std::string> roles;      // the model's joints' roles; empty: size/axis not judged
  std::string target_up;               // the model's up axis ("" = not judged)
  bool strict = false;                 // a doubt is a FormatError naming the history
};

// The gate as `predict` runs it on history frames [t_his, J, 3] (metres, the model's frame)
// about to be forecast: their doubts, plus those among `read_notes` ("warning: " notes of reading
// the file) as kReadingDoubt ones. With gate.strict a doubt is a FormatError naming `name` and the
// frames from `start`. Call only with the gate on.
HistoryCheck GateHistory(const Forecaster& forecaster, const PoseValidator& judge,
                         const HistoryGate& gate, const std::vector<std::string>& read_notes,
                         const std::vector<float>& history, const std::string& name, int start);

// The gate for a model: its joints' roles (shipped rig conventions in config_dir), its up axis
// (its protocol's), and the HG-VAE `scorer` (may be null).
HistoryGate GateForModel(const Forecaster& forecaster, const std::string& config_dir,
                         const HgvaeModel* scorer, bool strict);

// A history to forecast from, on the forecaster's skeleton and frame rate.
struct HistoryInput {
  MotionWithGaps motion;  // the whole motion and its missing values
  std::string name;       // the file (or "" for an in-memory history), named in errors
  int start = -1;         // first history frame; -1 = the last t_his frames
};

// K futures of one history, each sample the history followed by its future ([K, t_his + t_pred,
// J, 3] metres in Prediction::positions), with the validity of every future and of the history
// when `validator` judges anything, and the gate's doubts about the (repaired) history when it is
// on (futures of a doubted history are not valid). Prediction::model is `model_dir`. Throws
// FormatError naming the history when it is too short, has missing values and no imputer, or (a
// strict gate) raises a doubt; std::invalid_argument for a bad request (unknown part, k outside
// 1..kMaxFutures).
Prediction PredictFutures(const Forecaster& forecaster, const std::string& model_dir,
                          const PoseValidator& validator, HistoryInput history,
                          const ForecastRequest& request, const HistoryRepair& repair = {},
                          const HistoryGate& gate = {});

// The prediction-file form of K futures [K, t_pred, J, 3] (metres) continuing `history`
// [t_his, J, 3]: each sample the history then its future, with the validity of every future and
// of the history when `judge` judges anything. Throws std::invalid_argument for other sizes.
Prediction AssemblePrediction(const Forecaster& forecaster, const std::string& model_dir,
                              const std::vector<float>& history, const std::vector<float>& futures,
                              const ForecastRequest& request, const PoseValidator& judge);

// Everything `motionfork predict` reads, by path.
struct PredictFiles {
  std::string model_dir;           // forecasting bundle (model.yaml + generator.pt)
  std::string history;             // motion file (.bvh, .npy, .csv)
  MotionInputOptions input;        // how to read it
  int start = -1;                  // first history frame; -1 = the last t_his frames
  std::vector<std::string> masks;  // extra missing values (needs imputer_dir)
  std::string imputer_dir;         // HG-VAE bundle, or ""
  std::string denoiser_dir;        // Motion-DVAE bundle, or ""
  // The gate scores every history with this HG-VAE bundle: "" = imputer_dir, else the model's
  // own (MODEL/hgvae) when it has one; "none" = no window score.
  std::string scorer_dir;
  bool gate = true;  // check every history before forecasting (input.strict: refuse on a doubt)
  // Also write every sample as BVH (OUT_00.bvh ...): on the history's own rig when it is a BVH
  // file (pipeline/export_on_rig.h), else on the model's skeleton (pipeline/export.h).
  bool bvh = false;
  ForecastRequest request;                 // k, seed, fixed parts, repair
  Precision precision = Precision::kAuto;  // the generator's products (precision.h)
};

// What the run saw on the way, for the caller to report.
struct PredictNotes {
  double resampled_from = 0;       // Hz of the history file when it was resampled to the model's
  std::vector<std::string> input;  // how the history's joints were mapped (ConformForModel)
  bool angle_ranges = false;       // the bundle's constraint set judged the futures
  bool prior = false;              // the bundle's pose prior scored them
  std::string scorer;              // the HG-VAE bundle whose window score judged the history
};

// Loads the bundles, reads the history and runs PredictFutures.
Prediction PredictFromFiles(const PredictFiles& files, PredictNotes* notes = nullptr);

// Called once per history of PredictManyFromFiles, one call at a time, in any order.
using PredictionDone =
    std::function<void(int history, const Prediction& prediction, const PredictNotes& notes)>;

// Many histories (files.history is not read) with one loading of the bundles: history i's
// prediction is the one PredictFromFiles gives for it alone (the same request and seed), made by
// up to `threads` threads (pin LibTorch to one thread each: PinThreads(1)). Every history is read
// and checked (length, missing values) before any is predicted, so that a bad file stops the run
// before `done` is called; an error names the file.
void PredictManyFromFiles(const PredictFiles& files, const std::vector<std::string>& histories,
                          int threads, const PredictionDone& done);

// Per-sample summary of a prediction's validity: futures valid (every judge), how many fail
// each judge, and the mean of their prior NLLs (0 when there is no prior).
struct ValiditySummary {
  int valid_futures = 0;
  int failing_angles = 0, failing_prior = 0, failing_history = 0;
  double mean_prior_nll = 0;
};
ValiditySummary Summarise(const Prediction& p);

}  // namespace motionfork::pipeline
