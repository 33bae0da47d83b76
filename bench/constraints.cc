// Benchmark: angle-range constraints.
//   1. the checker (no LibTorch), frames per second on one thread, for each shipped set;
//   2. the LibTorch penalty, forward + backward on a batch of 16 x 100 x 125 frames
//      ([1600, 125, J, 3]: 16 histories x 100 samples x 125 frames, H36M's window), one thread,
//      with the fused CPU kernel (the default) and with composed tensor ops (the reference).
//
//   bench_constraints [CONFIG_DIR]     (default: <source tree>/configs)
//
// Poses: a standing pose with N(0, 8 cm) noise per coordinate (the checker's cost does not depend
// on the values). Run on an idle machine; the figures go in BENCHMARKS.md.
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "constraints/torch/angle_penalty.h"
#include "torch_util/blas_core.h"

using namespace motionfork;

namespace {

// Standing poses (metres, x left, y up, z forward) in the protocol skeletons' joint order.
const std::vector<float> kH36mOrder = {  // also Bandai's 17 joints, same layout
    0,      1.00f,  0,     -0.13f, 0.98f,  0,      -0.13f, 0.55f, 0.03f, -0.13f, 0.10f,
    -0.02f, 0.13f,  0.98f, 0,      0.13f,  0.55f,  0.03f,  0.13f, 0.10f, -0.02f, 0,
    1.23f,  -0.01f, 0,     1.48f,  0,      0,      1.58f,  0.10f, 0,     1.72f,  0.01f,
    0.17f,  1.45f,  0,     0.19f,  1.17f,  -0.02f, 0.20f,  0.92f, 0.04f, -0.17f, 1.45f,
    0,      -0.19f, 1.17f, -0.02f, -0.20f, 0.92f,  0.04f};
const std::vector<float> kHumanEvaOrder = {
    0,      1.00f, 0,     0,      1.45f, 0,      0.17f,  1.42f, 0,      0.19f,  1.14f, -0.02f,
    0.20f,  0.89f, 0.04f, -0.17f, 1.42f, 0,      -0.19f, 1.14f, -0.02f, -0.20f, 0.89f, 0.04f,
    0.12f,  0.97f, 0,     0.12f,  0.55f, 0.03f,  0.12f,  0.10f, -0.02f, -0.12f, 0.97f, 0,
    -0.12f, 0.55f, 0.03f, -0.12f, 0.10f, -0.02f, 0,      1.68f, 0.02f};

std::vector<float> Noisy(const std::vector<float>& base, size_t frames, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, 0.08f);
  std::vector<float> out(base.size() * frames);
  for (size_t i = 0; i < out.size(); ++i) out[i] = base[i % base.size()] + n(rng);
  return out;
}

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  const std::string config_dir = argc > 1 ? argv[1] : MOTIONFORK_BENCH_CONFIG_DIR;
  torch::set_num_threads(1);
  torch::set_num_interop_threads(1);
  try {
    struct Case {
      std::string name;
      const std::vector<float>* pose;
    };
    const std::vector<Case> cases = {
        {"h36m", &kH36mOrder}, {"bandai", &kH36mOrder}, {"humaneva", &kHumanEvaOrder}};
    std::printf("checker, 1 thread (frames/s, best of 5 passes over 200,000 frames):\n");
    for (const Case& k : cases) {
      const SkeletonConfig skel =
          LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", k.name));
      const ConstraintSet set = ConstraintSet::Build(
          LoadConstraintConfig(ResolveConfigPath(config_dir, "constraints", k.name)),
          *skel.skeleton);
      const int frames = 200000;
      const std::vector<float> poses = Noisy(*k.pose, frames, 1);
      std::vector<float> angles(static_cast<size_t>(frames) * set.num_constraints());
      std::vector<AngleStatus> status(angles.size());
      const AngleChecker checker(set);
      double best = 1e9;
      for (int rep = 0; rep < 5; ++rep) {
        const auto t0 = std::chrono::steady_clock::now();
        checker.Run(poses.data(), frames, angles.data(), status.data());
        best = std::min(best, Seconds(t0));
      }
      long long violated = 0;
      for (AngleStatus s : status) violated += IsViolation(s);
      std::printf(
          "  %-9s %2d joints, %2d angles, %2d vector ops: %6.2f M frames/s  (%.0f ns/frame; "
          "%.1f%% of angles outside their range)\n",
          k.name.c_str(), set.num_joints(), set.num_constraints(), set.num_registers(),
          frames / best / 1e6, best / frames * 1e9, 100.0 * violated / status.size());
    }

    std::printf(
        "\npenalty, LibTorch %s, 1 thread, forward + backward on [1600, 125, J, 3] "
        "(200,000 frames; median of 5 after 1 warm-up):\n",
        TORCH_VERSION);
    for (const Case& k : cases) {
      const SkeletonConfig skel =
          LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", k.name));
      const ConstraintSet set = ConstraintSet::Build(
          LoadConstraintConfig(ResolveConfigPath(config_dir, "constraints", k.name)),
          *skel.skeleton);
      const int J = set.num_joints();
      const std::vector<float> poses = Noisy(*k.pose, 1600 * 125, 2);
      const torch::Tensor base =
          torch::from_blob(const_cast<float*>(poses.data()), {1600, 125, J, 3}).clone();
      for (bool fused : {true, false}) {
        AnglePenaltyOptions options;
        options.fused_cpu = fused;
        AnglePenalty penalty(set, options);
        std::vector<double> fwd, total;
        for (int rep = 0; rep < 6; ++rep) {
          torch::Tensor x = base.clone().requires_grad_(true);
          const auto t0 = std::chrono::steady_clock::now();
          torch::Tensor loss = penalty->forward(x);
          const double f = Seconds(t0);
          loss.backward();
          const double t = Seconds(t0);
          if (rep > 0) {
            fwd.push_back(f);
            total.push_back(t);
          }
        }
        std::sort(fwd.begin(), fwd.end());
        std::sort(total.begin(), total.end());
        std::printf("  %-9s %2d angles, %-20s forward %7.1f ms, forward + backward %7.1f ms\n",
                    k.name.c_str(), set.num_constraints(),
                    fused ? "fused CPU kernel:" : "composed tensor ops:", 1e3 * fwd[fwd.size() / 2],
                    1e3 * total[total.size() / 2]);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_constraints: %s\n", e.what());
    return 2;
  }
  return 0;
}
