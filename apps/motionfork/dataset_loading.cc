#include "dataset_loading.h"

#include <memory>
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "bundle/generator_bundle.h"
#include "config/config_paths.h"
#include "generator/inference/forecaster.h"

namespace motionfork::app {

Dataset LoadDatasetWithProgress(const ProtocolOptions& protocol, const SkeletonConfig& skeleton,
                                const std::string& data_dir, const std::string& split_file,
                                const GlobalOptions& global) {
  DatasetLoadOptions load;
  load.cache_dir = CacheDir(global.cache_dir);
  load.split_file = split_file;
  ProgressBar bar("loading " + protocol.name, !global.quiet);
  load.progress = [&bar](const LoadProgress& p) { bar.Update(p.fraction, p.detail); };
  Dataset ds = LoadDataset(protocol, skeleton, data_dir, load);
  bar.Finish();
  return ds;
}

Dataset LoadProtocolDataset(const std::string& protocol, const std::string& data_dir,
                            const std::string& split_file, const GlobalOptions& global) {
  const std::string config_dir = ConfigDir(global.config_dir);
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", p.skeleton));
  return LoadDatasetWithProgress(p, skeleton, data_dir, split_file, global);
}

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

nlohmann::ordered_json ForecastingJson(const ForecastingFigures& f, const std::string& setting_key,
                                       const std::string& before, const std::string& after) {
  nlohmann::ordered_json settings = nlohmann::ordered_json::array();
  for (const RepairedForecast& s : f.settings) {
    settings.push_back({{setting_key, s.setting},
                        {"ade_" + before, s.before.ade},
                        {"fde_" + before, s.before.fde},
                        {"ade_" + after, s.after.ade},
                        {"fde_" + after, s.after.fde}});
  }
  return {{"forecaster", f.forecaster}, {"k", f.k},
          {"windows", f.windows},       {"repair", false},
          {"ade_clean", f.clean.ade},   {"fde_clean", f.clean.fde},
          {"settings", settings}};
}

}  // namespace motionfork::app
