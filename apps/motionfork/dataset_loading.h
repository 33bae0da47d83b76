// Loading a protocol's dataset from an app, with a progress bar and the cache folder: the one
// place subcommands do it.
#pragma once

#include <string>

#include "commands.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"

namespace motionfork::app {

// split_file: overrides the protocol's split file ("" = the protocol's).
Dataset LoadDatasetWithProgress(const ProtocolOptions& protocol, const SkeletonConfig& skeleton,
                                const std::string& data_dir, const std::string& split_file,
                                const GlobalOptions& global);

}  // namespace motionfork::app
