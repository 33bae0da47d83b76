#include "eval/history_forecasting.h"

#include <algorithm>
#include <stdexcept>

namespace motionfork {

HistoryForecastProbe::HistoryForecastProbe(const TestSet& test_set, int max_windows, int k,
                                           HistoryForecaster forecaster)
    : test_set_(&test_set), k_(k), forecaster_(std::move(forecaster)) {
  if (forecaster_.t_his != test_set.t_his) {
    throw std::invalid_argument(forecaster_.name + ": expected a forecaster of " +
                                std::to_string(test_set.t_his) + " history frames, got " +
                                std::to_string(forecaster_.t_his));
  }
  const int total = test_set.num_windows(), count = std::min(max_windows, total);
  const size_t future = static_cast<size_t>(test_set.t_pred) * test_set.pose_dims;
  for (int i = 0; i < count; ++i) {
    const int w = static_cast<int>(static_cast<int64_t>(i) * total / count);
    windows_.push_back(w);
    futures_.insert(futures_.end(), test_set.future(w), test_set.future(w) + future);
  }
}

std::vector<float> HistoryForecastProbe::Histories() const {
  std::vector<float> out;
  for (int w : windows_) {
    AppendPoseVectors(test_set_->history(w), test_set_->t_his, test_set_->num_joints(), &out);
  }
  return out;
}

Displacement HistoryForecastProbe::Score(const std::vector<float>& histories) const {
  return MeanMinDisplacement(forecaster_.forecast(histories, count()), futures_, count(), k_,
                             test_set_->t_pred, test_set_->pose_dims);
}

void AppendPoseVectors(const float* positions, int frames, int joints, std::vector<float>* out) {
  const int D = 3 * (joints - 1);
  for (int t = 0; t < frames; ++t) {
    const float* f = positions + static_cast<size_t>(t) * joints * 3;
    for (int v = 0; v < D; ++v) out->push_back(f[3 + v] - f[v % 3]);
  }
}

}  // namespace motionfork
