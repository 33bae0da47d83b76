#include "experiment_common.h"

#include "app_common.h"
#include "config/protocol_dataset.h"

namespace motionfork::app {

Dataset LoadProtocolDataset(const std::string& protocol, const std::string& data_dir,
                            const std::string& split_file, const GlobalOptions& global) {
  StageBars bars(!global.quiet);
  Dataset ds = motionfork::LoadProtocolDataset(
      {protocol, data_dir, split_file, ConfigDir(global.config_dir), CacheDir(global.cache_dir)},
      bars.Callback());
  bars.Finish();
  return ds;
}

}  // namespace motionfork::app
