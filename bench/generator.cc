// Benchmark: generator inference and training step at GSPS's Human3.6M sizes, one thread.
//
//   bench_generator [--threads N]
//
// Sizes: 16 nodes, t_his 25, t_pred 100, n_pre 10, hidden 256, 4 blocks, nz 64, 2 parts.
// Prints, for the fused path (FusedGenerator on its AVX-512 kernels) and for the LibTorch network:
// ms for 50 futures of one history; histories/s for 16 histories x 50 futures; FLOPs and achieved
// GFLOP/s of the graph-conv products; the process's peak resident memory after each stage; the
// network's training step (forward + backward, no losses).
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "fma_peak.h"
#include "generator/inference/fused_generator.h"
#include "generator/kernels/backend.h"
#include "generator/kernels/bf16_product.h"
#include "generator/model/generator_net.h"
#include "generator_sizes.h"
#include "peak_memory.h"
#include "torch_util/blas_core.h"
#include "torch_util/malloc_tuning.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

double Seconds(const std::chrono::steady_clock::time_point& t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Multiply-adds of one generator pass per sample (graph-conv products only).
double MacsPerSample(const GeneratorOptions& o, int parts) {
  const double N = o.num_nodes, C = o.coeff_features(), H = o.hidden, Z = o.nz;
  const double input = N * C * H + Z * H + N * N * H;
  const double hidden = 2 * o.blocks * (N * H * H + N * N * H);
  const double output = N * H * C + N * N * C;
  return parts * (input + hidden + output);
}

// Median over `reps` of the time for 16 histories x 50 futures run one history at a time.
template <typename Run>
double SixteenOneAtATime(Run& run, int reps) {
  std::vector<double> totals;
  for (int r = 0; r < reps; ++r) {
    double total = 0;
    for (int i = 0; i < 16; ++i) total += run(1, 50, 1);
    totals.push_back(total);
  }
  std::sort(totals.begin(), totals.end());
  return totals[totals.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  motionfork::KeepFreedMemory();
  int threads = 1;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
  }
  PinThreads(threads);
  torch::manual_seed(0);
  const GeneratorOptions o = bench::H36mGeneratorOptions();
  GeneratorNet net(o, bench::TwoParts16());
  net->eval();
  int64_t params = 0;
  for (const auto& p : net->parameters()) params += p.numel();
  std::printf("generator: %lld parameters, %d thread(s)\n", static_cast<long long>(params),
              threads);
  const double gflop_per_sample = 2 * MacsPerSample(o, 2) / 1e9;

  std::printf("peak resident memory with the network built: %.0f MB\n",
              bench::PeakResidentMegabytes());
  // The fused path on its AVX-512 kernels (FusedGenerator, what Forecaster uses; on CPUs
  // without AVX-512 it runs the portable kernels, which bench_products compares): same work.
  if (kernels::ActiveBackend() == kernels::Backend::kAvx512) {
    // The core's peak varies on this machine kind (up to 20% between hours): measured here,
    // before and after, so that the share of peak compares runs.
    bench::PeakGflops(20000000);
    const double peak_before = bench::PeakGflops(100000000);
    const FusedGenerator fast(*net);
    auto run_on = [&](const FusedGenerator& g, int64_t histories, int64_t k, int reps) {
      const torch::Tensor h = torch::randn({histories, o.t_his, o.num_nodes, 3});
      std::vector<float> out(static_cast<size_t>(histories * k) * o.t_pred * o.num_nodes * 3);
      std::vector<double> times;
      for (int r = 0; r < reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const torch::Tensor z0 = torch::randn({histories * k, o.nz}),
                            z1 = torch::randn({histories * k, o.nz});
        g.Predict(h.data_ptr<float>(), histories, k, {z0.data_ptr<float>(), z1.data_ptr<float>()},
                  {}, out.data());
        times.push_back(Seconds(t0));
      }
      std::sort(times.begin(), times.end());
      return times[times.size() / 2];
    };
    auto run_fast = [&](int64_t histories, int64_t k, int reps) {
      return run_on(fast, histories, k, reps);
    };
    run_fast(1, 50, 5);
    const double f1 = run_fast(1, 50, 41);
    const double peak = 0.5 * (peak_before + bench::PeakGflops(100000000));
    std::printf("AVX-512 multiply-add peak now: %.1f GFLOP/s\n", peak);
    std::printf(
        "fused: 50 futures of 1 history: %.2f ms median (%.1f GFLOP/s, %.0f%% of that peak)\n",
        f1 * 1e3, 50 * gflop_per_sample / f1, 100 * 50 * gflop_per_sample / f1 / peak);
    if (kernels::Bf16KernelRuns()) {
      // Experimental (issue 30): the hidden layers' products with bf16 inputs, A/B in turns
      // with float32 (medians of 7 rounds of 41 calls each).
      const FusedGenerator fast16(*net, ProductPrecision::kBf16);
      std::vector<double> t32, t16;
      for (int round = 0; round < 7; ++round) {
        t32.push_back(run_on(fast, 1, 50, 41));
        t16.push_back(run_on(fast16, 1, 50, 41));
      }
      std::sort(t32.begin(), t32.end());
      std::sort(t16.begin(), t16.end());
      std::printf(
          "fused, hidden products in bf16 (AVX512-BF16, vdpbf16ps peak %.1f GFLOP/s): 50 futures "
          "of 1 history %.2f ms against float32's %.2f ms in the same rounds (%.2fx)\n",
          bench::PeakBf16Gflops(100000000), t16[3] * 1e3, t32[3] * 1e3, t32[3] / t16[3]);
    }
    const double per = SixteenOneAtATime(run_fast, 9);
    std::printf(
        "fused: 16 histories x 50 futures, one history at a time: %.1f ms median = %.1f "
        "histories/s\n",
        per * 1e3, 16 / per);
    // What Forecaster needs (it runs about 64 samples at a time), before the one-call run below
    // makes scratch for 800 samples.
    std::printf("peak resident memory after the fused inference, one history at a time: %.0f MB\n",
                bench::PeakResidentMegabytes());
    const double f16 = run_fast(16, 50, 9);
    std::printf(
        "fused: 16 histories x 50 futures in one call: %.1f ms median = %.1f histories/s (%.1f "
        "GFLOP/s)\n",
        f16 * 1e3, 16 / f16, 16 * 50 * gflop_per_sample / f16);
    std::printf("peak resident memory after the fused inference: %.0f MB\n",
                bench::PeakResidentMegabytes());
  }

  auto run = [&](int64_t histories, int64_t k, int reps) {
    torch::NoGradGuard no_grad;
    const torch::Tensor h = torch::randn({histories, o.t_his, o.num_nodes, 3});
    std::vector<double> times;
    for (int r = 0; r < reps; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      std::vector<torch::Tensor> z = {torch::randn({histories * k, o.nz}),
                                      torch::randn({histories * k, o.nz})};
      const torch::Tensor y = net->forward(h, z);
      times.push_back(Seconds(t0));
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
  };
  run(1, 50, 3);  // warm up
  const double one = run(1, 50, 21);
  std::printf("50 futures of 1 history: %.2f ms median (%.2f GFLOP, %.1f GFLOP/s)\n", one * 1e3,
              50 * gflop_per_sample, 50 * gflop_per_sample / one);
  const double batch = run(16, 50, 7);
  std::printf("16 histories x 50 futures: %.1f ms median = %.1f histories/s (%.1f GFLOP/s)\n",
              batch * 1e3, 16 / batch, 16 * 50 * gflop_per_sample / batch);
  // The same work one history at a time, as Forecaster::PredictRootRelative chunks it (the
  // activations of 50 samples stay in cache).
  const double per16 = SixteenOneAtATime(run, 7);
  std::printf(
      "16 histories x 50 futures, one history at a time: %.1f ms median = %.1f histories/s (%.1f "
      "GFLOP/s)\n",
      per16 * 1e3, 16 / per16, 16 * 50 * gflop_per_sample / per16);

  std::printf("peak resident memory after LibTorch's inference: %.0f MB\n",
              bench::PeakResidentMegabytes());

  // Training step of the network alone (forward + backward of a squared loss), 16 x 100 futures.
  net->train();
  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(1e-3));
  const torch::Tensor h = torch::randn({16, o.t_his, o.num_nodes, 3});
  std::vector<double> steps;
  for (int r = 0; r < 4; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<torch::Tensor> z = {torch::randn({1600, o.nz}), torch::randn({1600, o.nz})};
    adam.zero_grad();
    net->forward(h, z).pow(2).mean().backward();
    adam.step();
    steps.push_back(Seconds(t0));
  }
  std::sort(steps.begin(), steps.end());
  std::printf("network training step, 16 histories x 100 futures (no losses): %.2f s median\n",
              steps[steps.size() / 2]);
  std::printf("peak resident memory after the training steps: %.0f MB\n",
              bench::PeakResidentMegabytes());
  return 0;
}
