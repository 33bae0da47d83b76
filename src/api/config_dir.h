// The configs folder the API uses (LoadOptions::config_dir, FileReadOptions::config_dir).
#pragma once

#include <string>

namespace motionfork {

// `given` or $MOTIONFORK_CONFIG_DIR when set (must be a folder; std::invalid_argument otherwise),
// else the installed configs, else the source tree's; "" when none exists.
std::string FindConfigDir(const std::string& given);

}  // namespace motionfork
