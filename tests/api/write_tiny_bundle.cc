// write_tiny_bundle OUT_DIR: OUT_DIR/bundle (tests/api/tiny_bundle.h) and OUT_DIR/history.csv
// (20 walking frames on its joints), for tests that run programs on a bundle (the example, the
// find_package consumer).
#include <cstdio>
#include <exception>
#include <filesystem>

#include "io/motion_file.h"
#include "tiny_bundle.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path out = argv[1];
    std::filesystem::create_directories(out);
    motionfork::testing::WriteTinyBundle((out / "bundle").string(), MOTIONFORK_CONFIG_DIR);
    motionfork::WriteMotionFile((out / "history.csv").string(),
                                motionfork::testing::TinyBundleHistory(20));
    std::printf("wrote %s/bundle and %s/history.csv\n", argv[1], argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_tiny_bundle: %s\n", e.what());
    return 1;
  }
  return 0;
}
