#include "generator/training/history_forecaster.h"

#include <memory>
#include <vector>

#include "bundle/generator_bundle.h"
#include "generator/inference/forecaster.h"

namespace motionfork {

HistoryForecaster LoadHistoryForecaster(const std::string& dir, int k, uint64_t seed) {
  if (dir.empty()) return {};
  auto fc = std::make_shared<const Forecaster>(LoadForecaster(dir));
  ForecastRequest request;
  request.k = k;
  request.seed = seed;
  request.repair = false;
  return {dir, fc->config().generator.t_his, fc->skeleton()->joint_names(),
          [fc, request](const std::vector<float>& histories, int count) {
            return fc->PredictRootRelative(histories, count, request);
          }};
}

}  // namespace motionfork
