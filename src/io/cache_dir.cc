#include "io/cache_dir.h"

#include <cstdlib>
#include <filesystem>

namespace motionfork {

std::string CacheDir(const std::string& flag_value) {
  if (flag_value == "none") return "";
  if (!flag_value.empty()) return flag_value;
  if (const char* env = std::getenv("MOTIONFORK_CACHE_DIR"); env && *env) {
    return std::string(env) == "none" ? "" : env;
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    return (std::filesystem::path(xdg) / "motionfork").string();
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return (std::filesystem::path(home) / ".cache" / "motionfork").string();
  }
  return (std::filesystem::temp_directory_path() / "motionfork-cache").string();
}

}  // namespace motionfork
