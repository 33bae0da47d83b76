#include "experiment_common.h"

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
  load.warning = PrintWarning;
  Dataset ds = LoadDataset(p, skeleton, data_dir, load);
  bar.Finish();
  return ds;
}

}  // namespace motionfork::app
