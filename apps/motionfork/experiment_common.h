// What the subcommands that run on a protocol's data share: its dataset, loaded with a progress bar
// and the cache folder.
#pragma once

#include <string>

#include "commands.h"
#include "dataset/dataset.h"

namespace motionfork::app {

// protocol: a name or path (looked up in the configs folder); split_file overrides the protocol's
// split file ("" = the protocol's).
Dataset LoadProtocolDataset(const std::string& protocol, const std::string& data_dir,
                            const std::string& split_file, const GlobalOptions& global);

}  // namespace motionfork::app
