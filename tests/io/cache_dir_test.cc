#include "io/cache_dir.h"

#include <catch2/catch.hpp>
#include <cstdlib>

namespace motionfork {

TEST_CASE("cache folder: the flag, then MOTIONFORK_CACHE_DIR, then XDG_CACHE_HOME; none disables") {
  setenv("MOTIONFORK_CACHE_DIR", "/tmp/mf-env", 1);
  setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
  CHECK(CacheDir("/tmp/flag") == "/tmp/flag");
  CHECK(CacheDir("none").empty());
  CHECK(CacheDir("") == "/tmp/mf-env");
  setenv("MOTIONFORK_CACHE_DIR", "none", 1);
  CHECK(CacheDir("").empty());
  unsetenv("MOTIONFORK_CACHE_DIR");
  CHECK(CacheDir("") == "/tmp/xdg/motionfork");
  unsetenv("XDG_CACHE_HOME");
  setenv("HOME", "/tmp/home", 1);
  CHECK(CacheDir("") == "/tmp/home/.cache/motionfork");
}

}  // namespace motionfork
