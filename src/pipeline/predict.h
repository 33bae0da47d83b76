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

// A history to forecast from, on the forecaster's skeleton and frame rate.
struct HistoryInput {
  MotionWithGaps motion;  // the whole motion and its missing values
  std::string name;       // the file (or "" for an in-memory history), named in errors
  int start = -1;         // first history frame; -1 = the last t_his frames
};

// K futures of one history, each sample the history followed by its future ([K, t_his + t_pred,
// J, 3] metres in Prediction::positions), with the validity of every future and of the history
// when `validator` judges anything. Prediction::model is `model_dir`. Throws FormatError naming the
// history when it is too short or has missing values and no imputer, std::invalid_argument for a
// bad request (unknown part, k outside 1..kMaxFutures).
Prediction PredictFutures(const Forecaster& forecaster, const std::string& model_dir,
                          const PoseValidator& validator, HistoryInput history,
                          const ForecastRequest& request, const HistoryRepair& repair = {});

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
  ForecastRequest request;         // k, seed, fixed parts, repair
};

// What the run saw on the way, for the caller to report.
struct PredictNotes {
  double resampled_from = 0;       // Hz of the history file when it was resampled to the model's
  std::vector<std::string> input;  // how the history's joints were mapped (ConformForModel)
  bool angle_ranges = false;       // the bundle's constraint set judged the futures
  bool prior = false;              // the bundle's pose prior scored them
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

// Per-sample summary of a prediction's validity: futures valid in every frame and the mean of
// their prior NLLs (0 when there is no prior).
struct ValiditySummary {
  int valid_futures = 0;
  double mean_prior_nll = 0;
};
ValiditySummary Summarise(const Prediction& p);

}  // namespace motionfork::pipeline
