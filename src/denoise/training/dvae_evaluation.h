// The `motionfork dvae eval` experiment: a Motion-DVAE's denoising figures on its protocol's test
// split — error of noisy, filtered (the classical baselines, each tuned on training clips),
// denoised (regression mode), refined (refiner mode, where the bundle has a refiner) and optimised
// (optimisation mode) motion against the clean one for each noise kind, acceleration against the
// clean motion's, speed and, given a forecaster, the forecasting ADE/FDE from noisy and denoised
// histories. Part of the denoise training target: it reads datasets.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/progress.h"
#include "dataset/dataset.h"
#include "denoise/dvae_model.h"
#include "eval/history_forecasting.h"

namespace motionfork {

struct DvaeEvalOptions {
  std::vector<std::string> noises = {"gaussian:0",        "gaussian:0.01", "gaussian:0.02",
                                     "gaussian:0.05",     "gaussian:0.10", "outliers:0.1,0.3",
                                     "outliers:0.05,0.5", "jitter:0.02",   "jitter:0.05"};
  int clips = 200;              // test clips used, spread evenly
  int optimisation_clips = 20;  // of those, how many optimisation mode runs on
  // Training clips (spread evenly) on which each filter's parameters are chosen for each noise
  // kind, with noise of other seeds: the test clips are never used to tune a baseline.
  int tuning_clips = 50;
  int threads = 1;  // filter tuning
  uint64_t seed = 0;
  DenoiseOptions denoise;        // the mode is set per column
  HistoryForecaster forecaster;  // forecast empty = no forecasting figures
  int forecast_windows = 300;
  int k = 50;
  // Test and tuning clips played this many times slower (core/resample.h SlowDown; 1: as they
  // are): how the denoiser fares on slower motion than it was trained on (not the forecasting).
  double slow = 1;
};

// A classical filter with the parameters that did best on the tuning clips for one noise kind.
struct FilterFigure {
  std::string filter;          // FilterName
  std::string setting;         // DescribeFilter of the chosen parameters
  double tuning_cm = 0;        // its error on the tuning clips
  double cm = 0, removed = 0;  // on the test clips; removed: 1 - cm / noisy_cm
  double accel_ratio = 0;
};

// One noise kind. Errors: mean joint error in cm; accel_ratio_*: mean acceleration over the clean
// motion's; optimised figures NaN when optimisation mode runs on no clip.
struct DenoisingRow {
  std::string noise;
  double noisy_cm = 0, denoised_cm = 0, removed = 0;
  double optimised_cm = 0, optimised_noisy_cm = 0, removed_optimised = 0;
  double accel_ratio_noisy = 0, accel_ratio_denoised = 0, accel_ratio_optimised = 0;
  // Refiner mode (NaN when the bundle has no refiner).
  double refined_cm = NAN, removed_refined = NAN, accel_ratio_refined = NAN;
  std::vector<FilterFigure> filters;  // Gaussian, Savitzky-Golay, one-euro, Hampel
  // The filter of lowest test error (null when there is none).
  const FilterFigure* best_filter() const;
};

struct DvaeEvaluation {
  int clips = 0;
  int tuning_clips = 0;
  long long tuning_frames = 0;
  long long frames = 0;
  int optimisation_clips = 0;
  long long optimisation_frames = 0;
  std::string test_style;  // subject of the test clips (a style unseen in training)
  double clean_accel = 0;  // m/s^2
  double slow = 1;         // DvaeEvalOptions::slow
  int samples = 0;         // posterior draws
  int iterations = 0;      // optimisation mode
  std::vector<DenoisingRow> settings;
  double regression_frames_per_s = 0, optimisation_frames_per_s = 0;
  bool refiner = false;  // the bundle has one: refined figures and its speed
  double refiner_frames_per_s = 0;
  std::optional<ForecastingFigures> forecasting;  // before: noisy, after: denoised histories
};

// report: called once the clips are chosen (settings empty) and after each row; may be empty.
DvaeEvaluation EvaluateDvae(const DvaeModel& model, const Dataset& dataset,
                            const DvaeEvalOptions& options,
                            const std::function<void(const DvaeEvaluation&)>& report = {});

}  // namespace motionfork
