#include "generator/training/generator_predictor.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "io/clip_cache.h"
#include "io/file_util.h"

namespace motionfork {

GeneratorPredictor::GeneratorPredictor(Forecaster forecaster, std::string name,
                                       std::string bundle_hash, bool repair)
    : forecaster_(std::move(forecaster)),
      name_(std::move(name)),
      hash_(std::move(bundle_hash)),
      repair_(repair) {}

std::string GeneratorPredictor::description() const {
  const GeneratorOptions& g = forecaster_.config().generator;
  return "GSPS-style generator (" + forecaster_.config().protocol + ", n_pre " +
         std::to_string(g.n_pre) + ", hidden " + std::to_string(g.hidden) + ", " +
         std::to_string(forecaster_.parts().num_parts()) + " parts" +
         (forecaster_.repairs() ? (repair_ ? ", angle-range repair on" : ", angle-range repair off")
                                : "") +
         ", " + PrecisionName(forecaster_.precision()) + " products)";
}

void GeneratorPredictor::DoPredict(const float* history, const PredictRequest& request,
                                   float* futures) {
  ForecastRequest req;
  req.k = request.num_samples;
  req.seed = request.seed;
  req.repair = repair_;
  if (request.fixed_part >= 0) req.fixed_parts = {forecaster_.parts().names.at(request.fixed_part)};
  const std::vector<float> y = forecaster_.PredictWorld(history, req);
  std::copy(y.begin(), y.end(), futures);
}

std::string GeneratorBundleHash(const std::string& bundle_dir) {
  const std::string bytes =
      ReadFileBytes((std::filesystem::path(bundle_dir) / "generator.pt").string());
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(Fnv1a64(bytes)));
  return hex;
}

}  // namespace motionfork
