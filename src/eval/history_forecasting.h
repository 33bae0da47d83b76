// Forecasting from repaired histories: how much an imputed or denoised history helps a forecaster,
// measured on a protocol's test windows (the HG-VAE's and the Motion-DVAE's downstream figures).
// The forecaster comes in as a function, so this module does not depend on the generator.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "eval/metrics.h"
#include "eval/test_set.h"

namespace motionfork {

// A forecaster as the experiments see it.
struct HistoryForecaster {
  std::string name;                 // e.g. its bundle folder, for messages and reports
  int t_his = 0;                    // history frames it reads
  std::vector<std::string> joints;  // joint names of its skeleton, root first
  // histories [count, t_his, D] root-relative pose vectors (root dropped), metres -> futures
  // [count, K, t_pred, D]; K is the caller's (HistoryForecastProbe::k).
  std::function<std::vector<float>(const std::vector<float>& histories, int count)> forecast;
};

// Up to `max_windows` test windows spread evenly over a test set (window i * N / count), their
// true futures, and the ADE/FDE (MeanMinDisplacement) of K forecasts from a version of their
// histories.
class HistoryForecastProbe {
 public:
  HistoryForecastProbe(const TestSet& test_set, int max_windows, int k,
                       HistoryForecaster forecaster);
  int count() const { return static_cast<int>(windows_.size()); }
  int k() const { return k_; }
  const std::vector<int>& windows() const { return windows_; }  // [count] test-set indices
  // The windows' clean histories as pose vectors [count, t_his, D].
  std::vector<float> Histories() const;
  // histories: [count, t_his, D].
  Displacement Score(const std::vector<float>& histories) const;

 private:
  const TestSet* test_set_;
  int k_;
  HistoryForecaster forecaster_;
  std::vector<int> windows_;
  std::vector<float> futures_;  // [count, t_pred, D]
};

// Positions [frames, J, 3] metres -> pose vectors appended to *out: [frames, 3 (J - 1)], each
// joint but the root relative to the root.
void AppendPoseVectors(const float* positions, int frames, int joints, std::vector<float>* out);

// The forecasting figures of one way of repairing histories.
struct RepairedForecast {
  std::string setting;  // the occlusion or noise setting
  Displacement before;  // from the damaged (mean-filled, noisy) histories
  Displacement after;   // from the repaired (imputed, denoised) ones
  // From histories repaired in other ways, e.g. {"spline", ...}, {"refiner", ...}.
  std::vector<std::pair<std::string, Displacement>> others;
};

struct ForecastingFigures {
  std::string forecaster;
  int k = 0;
  int windows = 0;
  Displacement clean;  // from the clean histories
  std::vector<RepairedForecast> settings;
};

}  // namespace motionfork
