// Benchmark: generator inference and training step at GSPS's Human3.6M sizes, one thread.
//
//   bench_generator [--threads N] [--reference SCRIPT]
//
// --reference bench/reference_gsps.py: the original GSPS generator in PyTorch (/usr/bin/python3 or
// $MOTIONFORK_PYTHON, with torch: Debian's python3-torch), in its own process on the same threads,
// timed in turns with the fused path (A/B interleaved); the ratio of the two is the figure that
// counts.
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
#include <memory>
#include <string>
#include <vector>

#include "fma_peak.h"
#include "generator/inference/fused_generator.h"
#include "generator/kernels/backend.h"
#include "generator/kernels/bf16_product.h"
#include "generator/model/generator_net.h"
#include "generator_sizes.h"
#include "peak_memory.h"
#include "reference_process.h"
#include "torch_util/blas_core.h"
#include "torch_util/malloc_tuning.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

double Seconds(const std::chrono::steady_clock::time_point& t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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
  std::string reference_script;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--reference") && i + 1 < argc) {
      reference_script = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_generator [--threads N] [--reference SCRIPT]\n");
      return 2;
    }
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
  const double gflop_per_sample = 2 * bench::MacsPerSample(o, 2) / 1e9;

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
    run_fast(1, 50, 46);  // warm-up
    const double peak = 0.5 * (peak_before + bench::PeakGflops(100000000));
    // The engines in turns (medians of 7 rounds; 41 calls a round each, 5 of the reference's):
    // float32, the hidden layers' products in bf16 where AVX512-BF16 runs (issue 30), and the
    // reference PyTorch code when asked for.
    std::unique_ptr<bench::ReferenceProcess> reference;
    if (!reference_script.empty())
      reference = bench::ReferenceProcess::Python(reference_script, threads);
    const bool bf16 = kernels::Bf16KernelRuns();
    std::unique_ptr<FusedGenerator> fast16;
    if (bf16) fast16 = std::make_unique<FusedGenerator>(*net, ProductPrecision::kBf16);
    std::vector<double> t32, t16, tref;
    for (int round = 0; round < 7; ++round) {
      t32.push_back(run_on(fast, 1, 50, 41));
      if (bf16) t16.push_back(run_on(*fast16, 1, 50, 41));
      if (reference) {
        std::vector<double> calls;
        for (int c = 0; c < 5; ++c) calls.push_back(reference->Run());
        std::sort(calls.begin(), calls.end());
        tref.push_back(calls[2]);
      }
    }
    auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    const double m32 = median(t32);
    std::printf("engines in turns (7 rounds), 50 futures of 1 history:\n");
    std::printf("  float32, AVX-512 FMA (peak %.1f GFLOP/s): %.2f ms, %.0f%% of that peak\n", peak,
                m32 * 1e3, 100 * 50 * gflop_per_sample / m32 / peak);
    if (bf16) {
      // The bf16 path's products: the later half of each part's hidden layers in bf16 (their
      // H x H products), everything else in float32; its share is of the best time the two
      // engines' measured peaks allow for that split of the work.
      const double peak16 = bench::PeakBf16Gflops(100000000), m16 = median(t16);
      const double gflop16 =  // the later half of the layers, 2 FLOP a multiply-add
          2 * (bench::HiddenProductMacsPerSample(o, 2) / 2) / 1e9;
      const double best = 50 * (gflop16 / peak16 + (gflop_per_sample - gflop16) / peak);
      std::printf(
          "  bf16 products in half the hidden layers, AVX512-BF16 (vdpbf16ps peak %.1f GFLOP/s, "
          "%.0f%% of the work): %.2f ms, %.0f%% of the best the two peaks allow, %.2fx float32\n",
          peak16, 100 * gflop16 / gflop_per_sample, m16 * 1e3, 100 * best / m16, m32 / m16);
    }
    if (reference) {
      const double mref = median(tref);
      std::printf(
          "  reference: GSPS's generator in PyTorch (%s, %lld parameters): %.2f ms; float32 "
          "%.2fx faster\n",
          reference_script.c_str(), reference->parameters(), mref * 1e3, mref / m32);
      if (bf16)
        std::printf("  bf16 products %.2fx faster than the reference\n", mref / median(t16));
    }
    std::printf("engine of --precision auto here: %s\n",
                bf16 ? "bf16 products, AVX512-BF16" : "float32, AVX-512 FMA");
    const double per = SixteenOneAtATime(run_fast, 9);
    std::printf(
        "fused: 16 histories x 50 futures, one history at a time: %.1f ms median = %.1f "
        "histories/s\n",
        per * 1e3, 16 / per);
    if (fast16) {
      auto run_fast16 = [&](int64_t histories, int64_t k, int reps) {
        return run_on(*fast16, histories, k, reps);
      };
      const double per_bf16 = SixteenOneAtATime(run_fast16, 9);
      std::printf(
          "fused, bf16 products (auto's engine here): 16 histories x 50 futures, one history at a "
          "time: %.1f ms median = %.1f histories/s\n",
          per_bf16 * 1e3, 16 / per_bf16);
    }
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
