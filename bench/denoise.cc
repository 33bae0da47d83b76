// Benchmark: Motion-DVAE denoising speed (frames per second), regression, refiner (with the
// bundle's blend) and optimisation modes.
//
//   bench_denoise MODEL_DIR [--threads N] [--frames F] [--samples S] [--iterations I]
//
// Input: the built-in demo walk (no data needed) on the model's skeleton with 5 cm Gaussian
// noise, F frames (default 3000 = 100 s at 30 Hz) as one sequence, and 30 separate sequences of
// 1 s (the batched case), and one 0.5 s forecaster history (the interactive case).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "bundle/dvae_bundle.h"
#include "core/demo_motion.h"
#include "core/motion_noise.h"
#include "denoise/dvae_model.h"
#include "torch_util/blas_core.h"
#include "torch_util/malloc_tuning.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

double Seconds(const std::chrono::steady_clock::time_point& t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Best of `reps` runs, seconds.
double Time(const DvaeModel& model, const std::vector<std::vector<float>>& seqs,
            const DenoiseOptions& o, int reps) {
  model.Denoise(seqs, o);  // warm-up
  double best = 1e30;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    model.Denoise(seqs, o);
    best = std::min(best, Seconds(t0));
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  UseFastBlasKernels(argv);
  KeepFreedMemory();
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fprintf(stderr,
                 "usage: bench_denoise MODEL_DIR [--threads N] [--frames F] [--samples S] "
                 "[--iterations I]\n");
    return 2;
  }
  int threads = 1, frames = 3000, samples = -1, iterations = -1;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--samples") && i + 1 < argc) samples = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--iterations") && i + 1 < argc) iterations = std::atoi(argv[++i]);
  }
  PinThreads(threads);
  const DvaeModel model = [&] {
    try {
      return LoadDvaeModel(argv[1]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_denoise: %s\n", e.what());
      std::exit(2);
    }
  }();
  DenoiseOptions reg = model.manifest().denoise;
  if (samples >= 0) reg.samples = samples;
  reg.mode = DenoiseMode::kRegression;
  DenoiseOptions opt = reg;
  opt.mode = DenoiseMode::kOptimisation;
  if (iterations >= 0) opt.iterations = iterations;
  DemoWalkOptions walk;
  walk.frames = frames;
  walk.fps = model.manifest().fps;
  const auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  const Motion noisy = AddNoise(MakeDemoWalk(skeleton, walk), ParseNoiseSpec("gaussian:0.05"), 1);
  const std::vector<float>& p = noisy.positions();
  const size_t fv = static_cast<size_t>(model.joints()) * 3;
  std::printf(
      "model %s: %s parameters, windows of %d frames every %d; %d thread(s); %d posterior "
      "draws%s\n",
      argv[1], std::to_string(model.num_parameters()).c_str(), model.window(), reg.stride, threads,
      reg.samples, reg.fuse ? ", fused output" : ", decoder output");
  const double whole = Time(model, {p}, reg, 3);
  std::printf("regression, one sequence of %d frames: %8.1f ms (%7.0f frames/s)\n", frames,
              1e3 * whole, frames / whole);
  std::vector<std::vector<float>> seconds;
  for (int s = 0; s < 30 && (s + 1) * 30 <= frames; ++s)
    seconds.emplace_back(p.begin() + s * 30 * fv, p.begin() + (s + 1) * 30 * fv);
  const double batched = Time(model, seconds, reg, 3);
  std::printf("regression, %zu sequences of 30 frames: %8.1f ms (%7.0f frames/s)\n", seconds.size(),
              1e3 * batched, seconds.size() * 30 / batched);
  const std::vector<std::vector<float>> history = {
      std::vector<float>(p.begin(), p.begin() + 15 * fv)};
  const double one = Time(model, history, reg, 20);
  std::printf("regression, one 15-frame history: %8.2f ms\n", 1e3 * one);
  if (model.manifest().refiner.enabled()) {  // the default mode of a bundle with a refiner
    DenoiseOptions ref = reg;
    ref.mode = DenoiseMode::kRefiner;
    const double r = Time(model, {p}, ref, 3);
    std::printf("refiner (blend %s), one sequence of %d frames: %8.1f ms (%7.0f frames/s)\n",
                model.manifest().refiner_blend.weights.empty() ? "none" : "fitted", frames, 1e3 * r,
                frames / r);
    std::printf("refiner, one 15-frame history: %8.2f ms\n", 1e3 * Time(model, history, ref, 20));
  }
  const std::vector<std::vector<float>> opt_seq = {
      std::vector<float>(p.begin(), p.begin() + std::min(frames, 300) * fv)};
  const double o = Time(model, opt_seq, opt, 1);
  std::printf(
      "optimisation (%d iterations), one sequence of %d frames: %8.1f ms (%7.0f frames/s)\n",
      opt.iterations, std::min(frames, 300), 1e3 * o, std::min(frames, 300) / o);
  return 0;
}
