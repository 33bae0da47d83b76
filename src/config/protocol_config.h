// Protocol configs (configs/protocols/*.yaml) -> ProtocolOptions (dataset/protocol_options.h).
// Keys and defaults are documented in configs/protocols/README.md.
#pragma once

#include <string>

#include "dataset/protocol_options.h"

namespace motionfork {

// Throws FormatError naming the file, line and key for a missing, mistyped or invalid value.
ProtocolOptions LoadProtocolConfig(const std::string& path);

}  // namespace motionfork
