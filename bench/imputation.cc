// Benchmark: HG-VAE imputation and scoring speed, one thread.
//
//   bench_imputation MODEL_DIR [--threads N] [--steps S]
//
// Windows are the model's own samples (no data needed), 10% of their values missing. Prints the
// time to impute one window (the interactive case: one forecaster history) and the batched
// throughput (256 windows at once), the refiner's fill of a whole motion (a bundle with one; 10%
// missing, and one joint missing for 15 frames: a sparse mask, whose probes hold copies of the
// gap) and the scoring throughput.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "bundle/hgvae_bundle.h"
#include "imputation/hgvae_model.h"
#include "imputation/occlusion.h"
#include "imputation/refiner_fills.h"
#include "torch_util/blas_core.h"
#include "torch_util/malloc_tuning.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

double Seconds(const std::chrono::steady_clock::time_point& t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  UseFastBlasKernels(argv);
  KeepFreedMemory();
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fprintf(stderr, "usage: bench_imputation MODEL_DIR [--threads N] [--steps S]\n");
    return 2;
  }
  int threads = 1, steps = -1;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::atoi(argv[++i]);
  }
  PinThreads(threads);
  const HgvaeModel model = [&] {
    try {
      return LoadHgvaeModel(argv[1]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_imputation: %s\n", e.what());
      std::exit(2);
    }
  }();
  ImputeOptions o = model.manifest().impute;
  if (steps >= 0) o.steps = steps;
  const int T = model.window(), N = model.coords();
  std::printf(
      "model %s: windows of %d frames x %d coordinates, %zu levels; %d threads, %d Adam steps (%s "
      "objective)\n",
      argv[1], T, N, model.manifest().model.levels.size(), threads, o.steps, ToString(o.objective));
  for (int batch : {1, 16, 256}) {
    const std::vector<float> w = model.Sample(batch, -1, 1);
    const std::vector<uint8_t> mask = RandomOcclusion(batch, T * N, 0.1, 2);
    model.Impute(w, mask, o);  // warm-up
    const int reps = batch == 1 ? 20 : batch == 16 ? 5 : 2;
    auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) model.Impute(w, mask, o);
    const double s = Seconds(t0) / reps;
    std::printf("impute %3d window%s: %8.1f ms  (%7.1f windows/s)\n", batch, batch == 1 ? " " : "s",
                1e3 * s, batch / s);
  }
  if (model.has_refiner()) {  // the refiner over a whole motion: the samples one after another
    struct Case {
      int windows;
      bool gap;  // one joint missing for 15 frames mid-motion instead of 10% at random
    };
    for (const Case c : {Case{1, false}, Case{64, false}, Case{64, true}}) {
      const int windows = c.windows;
      const std::vector<float> poses = model.Sample(windows, -1, 4);
      const int frames = windows * T, J = N / 3 + 1;
      std::vector<float> positions(static_cast<size_t>(frames) * J * 3, 0.0f);
      for (int t = 0; t < frames; ++t) {
        std::copy(poses.begin() + static_cast<size_t>(t) * N,
                  poses.begin() + static_cast<size_t>(t + 1) * N,
                  positions.begin() + static_cast<size_t>(t) * J * 3 + 3);
      }
      std::vector<uint8_t> missing = RandomOcclusion(1, frames * J * 3, 0.1, 5);
      for (int t = 0; t < frames; ++t)  // the root is always observed
        for (int a = 0; a < 3; ++a) missing[static_cast<size_t>(t) * J * 3 + a] = 0;
      if (c.gap) {
        std::fill(missing.begin(), missing.end(), 0);
        for (int t = frames / 2; t < frames / 2 + 15; ++t)
          for (int a = 0; a < 3; ++a) missing[(static_cast<size_t>(t) * J + J - 1) * 3 + a] = 1;
      }
      const std::vector<float> fallback(static_cast<size_t>(J) * 3, 0.0f);
      auto fill = [&] {
        return model.Refine(MakeRefinerFills(model.skeleton(), positions, missing, fallback));
      };
      fill();  // warm-up
      const int reps = windows == 1 ? 20 : 3;
      auto t0 = std::chrono::steady_clock::now();
      for (int r = 0; r < reps; ++r) fill();
      const double s = Seconds(t0) / reps;
      std::printf(
          "refiner, a motion of %4d frames, %-18s (fills included): %8.1f ms (%7.0f "
          "frames/s)\n",
          frames, c.gap ? "one 15-frame gap" : "10% missing", 1e3 * s, frames / s);
    }
  }
  const std::vector<float> w = model.Sample(1024, -1, 3);
  model.Score(w);
  auto t0 = std::chrono::steady_clock::now();
  model.Score(w);
  const double s = Seconds(t0);
  std::printf("score 1024 windows: %.1f ms (%.0f windows/s)\n", 1e3 * s, 1024 / s);
  return 0;
}
