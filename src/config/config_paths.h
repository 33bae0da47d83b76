// Finding shipped configs by name: "bandai" -> <config dir>/<kind>/bandai.yaml, or a path.
#pragma once

#include <string>
#include <vector>

namespace motionfork {

// name_or_path: an existing file path, or the name of a shipped config. config_dir: the shipped
// configs folder (holding skeletons/, protocols/, ...). Throws FormatError listing known names.
std::string ResolveConfigPath(const std::string& config_dir, const std::string& kind,
                              const std::string& name_or_path);

// Names of the shipped configs of a kind (file stems), sorted.
std::vector<std::string> ListConfigs(const std::string& config_dir, const std::string& kind);

}  // namespace motionfork
