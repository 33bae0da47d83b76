#include "generator/training/history_forecaster.h"

#include <memory>
#include <vector>

#include "bundle/generator_bundle.h"
#include "core/parallel_for.h"
#include "generator/inference/forecaster.h"

namespace motionfork {

HistoryForecaster LoadHistoryForecaster(const std::string& dir, int k, uint64_t seed, int threads) {
  if (dir.empty()) return {};
  auto fc = std::make_shared<const Forecaster>(LoadForecaster(dir));
  ForecastRequest request;
  request.k = k;
  request.seed = seed;
  request.repair = false;
  return {dir, fc->config().generator.t_his, fc->skeleton()->joint_names(),
          [fc, request, threads](const std::vector<float>& histories, int count) {
            // One history at a time, history i with ItemSeed(seed, i): the same futures for any
            // number of threads.
            const size_t in = histories.size() / static_cast<size_t>(count);
            std::vector<std::vector<float>> futures(static_cast<size_t>(count));
            ParallelFor(count, threads, [&](int i, int) {
              ForecastRequest r = request;
              r.seed = ItemSeed(request.seed, i);
              const auto first = histories.begin() + static_cast<std::ptrdiff_t>(i * in);
              futures[static_cast<size_t>(i)] = fc->PredictRootRelative(
                  std::vector<float>(first, first + static_cast<std::ptrdiff_t>(in)), 1, r);
            });
            std::vector<float> out;
            for (const std::vector<float>& f : futures) out.insert(out.end(), f.begin(), f.end());
            return out;
          }};
}

}  // namespace motionfork
