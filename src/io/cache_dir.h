// Where motionfork keeps its caches (parsed datasets, multimodal sets) unless told otherwise.
#pragma once

#include <string>

namespace motionfork {

// `flag_value` (a --cache-dir), else $MOTIONFORK_CACHE_DIR, else $XDG_CACHE_HOME/motionfork, else
// ~/.cache/motionfork, else a folder in the system's temporary folder. "none" (as the flag or the
// variable) disables caching: returns "".
std::string CacheDir(const std::string& flag_value);

}  // namespace motionfork
