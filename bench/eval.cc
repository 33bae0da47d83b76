// Benchmark: the whole evaluation of a protocol's test split (test windows, multimodal sets,
// both baselines at K samples), with the time spent in the predictor and in the metrics.
//
//   bench_eval [PROTOCOL] [DATA_DIR] [K] [CONFIG_DIR]
//   defaults: bandai ../shared/data/bandai 50 <source tree>/configs
//
// Prints the figures (so a run doubles as a check) and the seconds per stage. One thread (Eigen
// runs single-threaded here); run on an idle machine and say so when it was not.
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "eval/baselines.h"
#include "eval/evaluate.h"
#include "eval/test_set.h"
#include "torch_util/blas_core.h"

using namespace motionfork;

namespace {

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// wall: seconds of the whole Evaluate call; cpu: process CPU seconds over it (less sensitive to
// other processes on a shared machine than wall time).
void Report(const char* name, const EvalResult& r, double wall, double cpu) {
  const Figures& f = r.overall;
  const double both = r.seconds_predicting + r.seconds_metrics;
  std::printf("%-20s APD %.3f  ADE %.3f  FDE %.3f  MMADE %.3f  MMFDE %.3f\n", name, f.apd, f.ade,
              f.fde, f.mmade, f.mmfde);
  std::printf(
      "%-20s %.2f s wall (%.2f s CPU): predictor %.2f s (%.0f%%), metrics %.2f s (%.0f%%), "
      "%.2f ms/window\n",
      "", wall, cpu, r.seconds_predicting, 100 * r.seconds_predicting / both, r.seconds_metrics,
      100 * r.seconds_metrics / both, 1000 * wall / f.windows);
}

}  // namespace

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  const std::string protocol_name = argc > 1 ? argv[1] : "bandai";
  const std::string data = argc > 2 ? argv[2] : "../shared/data/bandai";
  const int k = argc > 3 ? std::stoi(argv[3]) : 50;
  const std::string config_dir = argc > 4 ? argv[4] : MOTIONFORK_BENCH_CONFIG_DIR;
  try {
    const ProtocolOptions p =
        LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", protocol_name));
    const SkeletonConfig s =
        LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", p.skeleton));
    const std::filesystem::path cache =
        std::filesystem::temp_directory_path() / "motionfork_bench_eval_cache";
    std::filesystem::remove_all(cache);
    DatasetLoadOptions load;
    load.cache_dir = cache.string();
    auto t0 = std::chrono::steady_clock::now();
    const Dataset ds = LoadDataset(p, s, data, load);
    const double load_s = Since(t0);
    std::vector<const Clip*> test;
    std::vector<const Motion*> train;
    for (const Clip& c : ds.clips) {
      if (c.split == Split::kTest) test.push_back(&c);
      if (c.split == Split::kTrain) train.push_back(&c.motion);
    }
    t0 = std::chrono::steady_clock::now();
    TestSet ts = BuildTestSet(test, p);
    const double windows_s = Since(t0);
    t0 = std::chrono::steady_clock::now();
    AttachMultimodalSets(&ts, p.multimodal_threshold, cache.string(), p.name);
    const double sets_s = Since(t0);
    t0 = std::chrono::steady_clock::now();
    const bool cached = AttachMultimodalSets(&ts, p.multimodal_threshold, cache.string(), p.name);
    const double sets_cached_s = Since(t0);
    std::printf("protocol %s, data %s, K = %d\n", p.name.c_str(), data.c_str(), k);
    std::printf("dataset load (parse, cold):   %.2f s\n", load_s);
    std::printf("test windows:                 %d from %zu clips, %.3f s\n", ts.num_windows(),
                test.size(), windows_s);
    std::printf(
        "multimodal sets (threshold %.2g m): %.3f s computed, %.3f s from the cache (%s); "
        "mean size %.1f\n",
        p.multimodal_threshold, sets_s, sets_cached_s, cached ? "hit" : "MISS",
        double(ts.multimodal.members.size()) / ts.num_windows());

    EvalOptions o;
    o.num_samples = k;
    o.keep_singleton_sets = p.keep_singleton_sets;
    ZeroVelocityPredictor zv(ts.skeleton, p.t_his, p.t_pred);
    t0 = std::chrono::steady_clock::now();
    std::clock_t c0 = std::clock();
    const EvalResult z = Evaluate(zv, ts, o);
    Report("zero-velocity", z, Since(t0), double(std::clock() - c0) / CLOCKS_PER_SEC);
    t0 = std::chrono::steady_clock::now();
    NearestNeighbourPredictor nn(train, p.t_his, p.t_pred);
    const double nn_setup = Since(t0);
    t0 = std::chrono::steady_clock::now();
    c0 = std::clock();
    const EvalResult n = Evaluate(nn, ts, o);
    Report("nearest-neighbours", n, Since(t0), double(std::clock() - c0) / CLOCKS_PER_SEC);
    std::printf("%-20s (%d training windows, set up in %.2f s)\n", "", nn.num_training_windows(),
                nn_setup);
    std::filesystem::remove_all(cache);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_eval: %s\n", e.what());
    return 2;
  }
  return 0;
}
