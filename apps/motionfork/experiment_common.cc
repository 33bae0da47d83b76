#include "experiment_common.h"

#include <cstdio>

#include "app_common.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"

namespace motionfork::app {

Dataset LoadProtocolDataset(const std::string& protocol, const std::string& data_dir,
                            const std::string& split_file, const GlobalOptions& global) {
  const std::string config_dir = ConfigDir(global.config_dir);
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", p.skeleton));
  DatasetLoadOptions load;
  load.cache_dir = CacheDir(global.cache_dir);
  load.split_file = split_file;
  ProgressBar bar("loading " + p.name, !global.quiet);
  load.progress = [&bar](const LoadProgress& lp) { bar.Update(lp.fraction, lp.detail); };
  Dataset ds = LoadDataset(p, skeleton, data_dir, load);
  bar.Finish();
  return ds;
}

void PrintRepairedForecasts(const ForecastingFigures& f, int width, const char* before,
                            const char* after) {
  for (const RepairedForecast& s : f.settings) {
    std::printf("  %-*s %s %.3f / %.3f   %s %.3f / %.3f\n", width, s.setting.c_str(), before,
                s.before.ade, s.before.fde, after, s.after.ade, s.after.fde);
  }
}

}  // namespace motionfork::app
