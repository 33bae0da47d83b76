#include "config/protocol_dataset.h"

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"

namespace motionfork {

DatasetLoadOptions ReportingLoadOptions(const std::string& cache_dir, const std::string& split_file,
                                        const StageProgress& progress, const std::string& stage) {
  DatasetLoadOptions load;
  load.cache_dir = cache_dir;
  load.split_file = split_file;
  load.progress = [progress, stage](const LoadProgress& p) {
    ReportProgress(progress, stage, p.fraction, p.detail);
  };
  load.warning = [progress](const std::string& w) { ReportWarning(progress, w); };
  return load;
}

Dataset LoadProtocolDataset(const ProtocolDatasetRequest& r, const StageProgress& progress) {
  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(r.config_dir, "protocols", r.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(r.config_dir, "skeletons", protocol.skeleton));
  return LoadDataset(
      protocol, skeleton, r.data,
      ReportingLoadOptions(r.cache_dir, r.split_file, progress, "loading " + protocol.name));
}

}  // namespace motionfork
