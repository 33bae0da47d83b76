// A protocol's dataset from its name: the protocol and skeleton configs looked up in the configs
// folder, then the data folder read (dataset/dataset.h), reporting as one stage.
#pragma once

#include <string>

#include "core/progress.h"
#include "dataset/dataset.h"

namespace motionfork {

struct ProtocolDatasetRequest {
  std::string protocol;               // a name (configs/protocols/NAME.yaml) or a YAML path
  std::string data;                   // the folder the protocol's source format reads
  std::string split_file;             // "" = the protocol's
  std::string config_dir, cache_dir;  // cache_dir "" = no cache
};

// Reports stage "loading <protocol name>" and the load's warnings (kWarningStage) to `progress`.
// Throws what LoadDataset and the config loaders throw.
Dataset LoadProtocolDataset(const ProtocolDatasetRequest& request,
                            const StageProgress& progress = {});

// DatasetLoadOptions that report to `progress` as `stage`, warnings as kWarningStage.
DatasetLoadOptions ReportingLoadOptions(const std::string& cache_dir, const std::string& split_file,
                                        const StageProgress& progress, const std::string& stage);

}  // namespace motionfork
