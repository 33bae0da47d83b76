#include "config/config_paths.h"

#include <algorithm>
#include <filesystem>

#include "core/error.h"

namespace motionfork {

std::vector<std::string> ListConfigs(const std::string& config_dir, const std::string& kind) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e :
       std::filesystem::directory_iterator(std::filesystem::path(config_dir) / kind, ec)) {
    if (e.path().extension() == ".yaml") names.push_back(e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string ResolveConfigPath(const std::string& config_dir, const std::string& kind,
                              const std::string& name_or_path) {
  namespace fs = std::filesystem;
  if (fs::is_regular_file(name_or_path)) return name_or_path;
  const fs::path shipped = fs::path(config_dir) / kind / (name_or_path + ".yaml");
  if (fs::is_regular_file(shipped)) return shipped.string();
  std::string known;
  for (const std::string& n : ListConfigs(config_dir, kind))
    known += (known.empty() ? "" : ", ") + n;
  throw FormatError("no " + kind + " config '" + name_or_path +
                    "': not a file, and not one of the " + "shipped names in " +
                    (fs::path(config_dir) / kind).string() + " (" +
                    (known.empty() ? "none found" : known) + ")");
}

}  // namespace motionfork
