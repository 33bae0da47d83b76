#include "generator/generator_predictor.h"

#include <cstdio>
#include <filesystem>

#include "io/clip_cache.h"
#include "io/file_util.h"

namespace motionfork {

GeneratorPredictor::GeneratorPredictor(Forecaster forecaster, std::string name, std::string bundle_hash)
    : forecaster_(std::move(forecaster)), name_(std::move(name)), hash_(std::move(bundle_hash)) {}

std::string GeneratorPredictor::description() const {
  const GeneratorOptions& g = forecaster_.config().generator;
  return "GSPS-style generator (" + forecaster_.config().protocol + ", n_pre " + std::to_string(g.n_pre) +
         ", hidden " + std::to_string(g.hidden) + ", " + std::to_string(forecaster_.parts().num_parts()) + " parts)";
}

void GeneratorPredictor::DoPredict(const float* history, const PredictRequest& request, float* futures) {
  const int J = skeleton().num_joints(), th = t_his(), tp = t_pred();
  std::vector<float> rel(static_cast<size_t>(th) * (J - 1) * 3);
  for (int t = 0; t < th; ++t) {
    const float* f = history + static_cast<size_t>(t) * J * 3;
    for (int j = 1; j < J; ++j)
      for (int a = 0; a < 3; ++a) rel[(static_cast<size_t>(t) * (J - 1) + j - 1) * 3 + a] = f[3 * j + a] - f[a];
  }
  ForecastRequest req;
  req.k = request.num_samples;
  req.seed = request.seed;
  if (request.fixed_part >= 0) req.fixed_parts = {forecaster_.parts().names.at(request.fixed_part)};
  const std::vector<float> y = forecaster_.PredictRootRelative(rel, 1, req);
  const float* root = history + static_cast<size_t>(th - 1) * J * 3;
  for (size_t s = 0; s < static_cast<size_t>(req.k) * tp; ++s) {
    float* out = futures + s * J * 3;
    for (int a = 0; a < 3; ++a) out[a] = root[a];
    for (int j = 1; j < J; ++j)
      for (int a = 0; a < 3; ++a) out[3 * j + a] = root[a] + y[(s * (J - 1) + j - 1) * 3 + a];
  }
}

std::string GeneratorBundleHash(const std::string& bundle_dir) {
  const std::string bytes = ReadFileBytes((std::filesystem::path(bundle_dir) / "generator.pt").string());
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(Fnv1a64(bytes)));
  return hex;
}

}  // namespace motionfork
