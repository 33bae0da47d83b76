// Benchmark: loading a whole dataset under a protocol, cold (parsing every file) and from the
// binary clip cache.
//
//   bench_dataset_load [PROTOCOL] [DATA_DIR] [CONFIG_DIR]
//   defaults: bandai ../shared/data/bandai <source tree>/configs
//
// Prints: clips, frames, cold seconds, cached seconds. Run on an idle machine; one thread.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "torch_util/blas_core.h"

using namespace motionfork;

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  const std::string protocol_name = argc > 1 ? argv[1] : "bandai";
  const std::string data = argc > 2 ? argv[2] : "../shared/data/bandai";
  const std::string config_dir = argc > 3 ? argv[3] : MOTIONFORK_BENCH_CONFIG_DIR;
  try {
    const ProtocolOptions p =
        LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", protocol_name));
    const SkeletonConfig s =
        LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", p.skeleton));
    const std::filesystem::path cache =
        std::filesystem::temp_directory_path() / "motionfork_bench_cache";
    std::filesystem::remove_all(cache);
    DatasetLoadOptions opts;
    opts.cache_dir = cache.string();
    auto time = [&](Dataset* out) {
      const auto t0 = std::chrono::steady_clock::now();
      *out = LoadDataset(p, s, data, opts);
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    Dataset cold, warm;
    const double cold_s = time(&cold);
    const double warm_s = time(&warm);
    long long frames = 0;
    for (const Clip& c : cold.clips) frames += c.motion.num_frames();
    std::printf("protocol %s, data %s\n", p.name.c_str(), data.c_str());
    std::printf("clips read: %zu usable + %zu skipped, usable frames: %lld\n", cold.clips.size(),
                cold.skipped.size(), frames);
    std::printf("cold load (parse + protocol + write cache): %.2f s\n", cold_s);
    std::printf("cached load (read cache + protocol):        %.2f s (from cache: %s)\n", warm_s,
                warm.from_cache ? "yes" : "NO");
    std::filesystem::remove_all(cache);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_dataset_load: %s\n", e.what());
    return 2;
  }
  return 0;
}
