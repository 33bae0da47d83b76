#include "dataset_loading.h"

#include "app_common.h"

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

}  // namespace motionfork::app
