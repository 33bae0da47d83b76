// Benchmark: every AVX-512 kernel of the generator (src/generator/kernels) against what would
// replace it if it were deleted, one thread, in one process, interleaved: each round runs every
// alternative once, in turn, so that all see the same state of the machine; medians over rounds.
//
//   bench_products [--rounds R] [--only NAME]
//
// Set OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 and pin the process (taskset -c 1) for figures.
// The A/Bs (the sizes; "portable" = the same call with kernels::UsePortableKernels(true)):
//   panel    kernels::MatMul vs LibTorch's mm (OpenBLAS) into a preallocated output, [M, 256] x
//            [256, 256] at M = 800 (50 futures x 16 nodes, inference) and M = 25,600 (16 histories
//            x 100 futures x 16 nodes, a training step's hidden layer); the portable MatMul too
//   bf16     where the CPU has AVX512-BF16: the core's float32 FMA and vdpbf16ps peaks, then
//            kernels::MatMulBf16 vs the float32 kernels::MatMul vs LibTorch's bf16 mm, the
//            panel sizes (issue 30)
//   tanh     kernels::Tanh on 800 x 256 floats, AVX-512 vs portable
//   mixrows  kernels::MixRows (graph mix + batch norm + tanh + residual) for 50 samples of a
//            hidden layer (16 nodes, 256 features), AVX-512 vs portable
//   fused    50 futures of one history at GSPS's Human3.6M sizes: FusedGenerator on AVX-512 vs on
//            portable kernels vs the LibTorch GeneratorNet (what MOTIONFORK_FAST_GENERATOR=0 runs)
// For each, the kernel's margin: (alternative's median / kernel's median - 1); the issue removes a
// kernel that does not beat its alternative by more than 10% (so went the node mix, the training
// weight product and the AVX-512 batch norm + tanh: BENCHMARKS.md, "Redesign A/B").
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "fma_peak.h"
#include "generator/inference/fused_generator.h"
#include "generator/kernels/backend.h"
#include "generator/kernels/bf16_product.h"
#include "generator/kernels/cpu_features.h"
#include "generator/kernels/panel_product.h"
#include "generator/kernels/tanh.h"
#include "generator/model/fused_ops.h"
#include "generator/model/generator_net.h"
#include "generator_sizes.h"
#include "torch_util/blas_core.h"
#include "torch_util/malloc_tuning.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

struct Alternative {
  std::string name;
  std::function<void()> run;
  bool portable = false;  // run with kernels::UsePortableKernels(true)
};

double Seconds(const Alternative& a) {
  kernels::UsePortableKernels(a.portable);
  const auto t0 = std::chrono::steady_clock::now();
  a.run();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  kernels::UsePortableKernels(false);
  return s;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Runs the alternatives in turn, `rounds` times (after one warm-up round), and prints each one's
// median and best; the first is the AVX-512 kernel, the others' margins are against it.
void AB(const char* title, const std::vector<Alternative>& alts, int rounds, double gflop = 0) {
  std::vector<std::vector<double>> times(alts.size());
  for (const Alternative& a : alts) Seconds(a);
  for (int r = 0; r < rounds; ++r)
    for (size_t i = 0; i < alts.size(); ++i) times[i].push_back(Seconds(alts[i]));
  std::printf("%s (%d interleaved rounds):\n", title, rounds);
  const double kernel = Median(times[0]);
  for (size_t i = 0; i < alts.size(); ++i) {
    const double median = Median(times[i]);
    const double best = *std::min_element(times[i].begin(), times[i].end());
    std::printf("  %-44s %9.3f ms median, best %9.3f ms", alts[i].name.c_str(), median * 1e3,
                best * 1e3);
    if (gflop > 0) std::printf(" (%5.1f GFLOP/s)", gflop / median);
    if (i > 0) std::printf("  kernel margin %+6.1f%%", 100 * (median / kernel - 1));
    std::printf("\n");
  }
}

bool Want(const char* only, const char* name) { return !only || !std::strcmp(only, name); }

}  // namespace

int main(int argc, char** argv) {
  UseFastBlasKernels(argv);
  KeepFreedMemory();
  int rounds = 0;
  const char* only = nullptr;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--rounds") && i + 1 < argc) rounds = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    if (!std::strcmp(argv[i], "--help")) {
      std::printf(
          "bench_products [--rounds R] [--only panel|bf16|tanh|mixrows|fused]:\n"
          "interleaved A/B of each AVX-512 kernel against its replacement, one thread\n");
      return 0;
    }
  }
  if (kernels::ActiveBackend() != kernels::Backend::kAvx512) {
    std::printf("the AVX-512 kernels do not run here (build or CPU): nothing to compare\n");
    return 0;
  }
  auto rounds_or = [&](int n) { return rounds > 0 ? rounds : n; };
  PinThreads(1);
  torch::manual_seed(0);
  std::printf("OpenBLAS core: %s\n", BlasCoreName().c_str());
  const int64_t K = 256, H = 256, N = 16;
  const torch::Tensor w = torch::randn({K, H});
  const kernels::PackedWeight packed = kernels::PackWeight(w.data_ptr<float>(), K, H);

  if (Want(only, "panel")) {
    for (const int64_t M : {int64_t{800}, int64_t{25600}}) {
      const torch::Tensor x = torch::randn({M, K});
      torch::Tensor z = torch::empty({M, H}), zt = torch::empty({M, H});
      auto matmul = [&] {
        kernels::MatMul(x.data_ptr<float>(), M, K, packed, z.data_ptr<float>());
      };
      const std::string title = "panel product [" + std::to_string(M) + ", 256] x [256, 256]";
      AB(title.c_str(),
         {{"AVX-512 panel kernel (weights packed once)", matmul},
          {"LibTorch mm (OpenBLAS), preallocated output", [&] { at::mm_out(zt, x, w); }},
          {"portable panel kernel", matmul, true}},
         rounds_or(M < 1000 ? 301 : 15), 2.0 * M * K * H / 1e9);
    }
  }
  if (Want(only, "bf16")) {
    if (!kernels::Bf16KernelRuns()) {
      std::printf("bf16: the AVX512-BF16 kernel does not run here (build or CPU)\n");
    } else {
      const kernels::PackedWeightBf16 packed16 = kernels::PackWeightBf16(w.data_ptr<float>(), K, H);
      const double fp32_peak = bench::PeakGflops(50000000),
                   bf16_peak = bench::PeakBf16Gflops(50000000);
      std::printf("core peak: float32 FMA %.1f GFLOP/s, vdpbf16ps %.1f GFLOP/s (%.2fx)\n",
                  fp32_peak, bf16_peak, bf16_peak / fp32_peak);
      for (const int64_t M : {int64_t{800}, int64_t{25600}}) {
        const torch::Tensor x = torch::randn({M, K});
        const torch::Tensor xb = x.to(torch::kBFloat16), wb = w.to(torch::kBFloat16);
        torch::Tensor z = torch::empty({M, H}), zb = torch::empty({M, H}, torch::kBFloat16);
        const std::string title = "bf16 product [" + std::to_string(M) + ", 256] x [256, 256]";
        AB(title.c_str(),
           {{"AVX512-BF16 kernel (X rounded as it enters)",
             [&] {
               kernels::MatMulBf16(x.data_ptr<float>(), M, K, packed16, z.data_ptr<float>());
             }},
            {"AVX-512 float32 panel kernel",
             [&] { kernels::MatMul(x.data_ptr<float>(), M, K, packed, z.data_ptr<float>()); }},
            {"LibTorch bf16 mm (inputs already bf16)", [&] { at::mm_out(zb, xb, wb); }}},
           rounds_or(M < 1000 ? 301 : 15), 2.0 * M * K * H / 1e9);
      }
    }
  }
  if (Want(only, "tanh")) {
    std::vector<float> v(800 * 256);
    const torch::Tensor src = torch::randn({800 * 256});
    auto run = [&] {
      std::memcpy(v.data(), src.data_ptr<float>(), v.size() * sizeof(float));
      kernels::Tanh(v.data(), static_cast<int64_t>(v.size()));
    };
    AB("tanh of 800 x 256 floats (copy in + tanh)",
       {{"AVX-512 tanh", run}, {"portable tanh", run, true}}, rounds_or(301));
  }
  if (Want(only, "mixrows")) {
    const int64_t samples = 50;
    kernels::AlignedFloats z(samples * N * H), adjacency(N * N), rowsum(N), scale(N * H),
        shift(N * H), out(samples * N * H), residual(samples * N * H);
    const torch::Tensor r = torch::randn({samples * N * H});
    std::memcpy(z.get(), r.data_ptr<float>(), sizeof(float) * samples * N * H);
    for (int64_t i = 0; i < samples * N * H; ++i) residual.get()[i] = 0.5f * z.get()[i];
    for (int64_t i = 0; i < N * N; ++i) adjacency.get()[i] = 0.1f * ((i * 7) % 5 - 2);
    for (int64_t i = 0; i < N * H; ++i) {
      scale.get()[i] = 1.0f + 0.001f * (i % 13);
      shift.get()[i] = 0.01f * (i % 7);
    }
    kernels::LayerEpilogue e;
    e.nodes = N;
    e.adjacency = adjacency.get();
    e.rowsum = rowsum.get();
    e.scale = scale.get();
    e.shift = shift.get();
    e.tanh = true;
    auto run = [&] {
      for (int64_t b = 0; b < samples; ++b) {
        kernels::MixRows(e, z.get() + b * N * H, H, H, nullptr, nullptr, N,
                         residual.get() + b * N * H, out.get() + b * N * H, H);
      }
    };
    AB("MixRows, 50 samples x 16 nodes x 256 features (mix, scale, shift, tanh, residual)",
       {{"AVX-512 MixRows", run}, {"portable MixRows", run, true}}, rounds_or(301));
  }
  if (Want(only, "fused")) {
    const GeneratorOptions o = bench::H36mGeneratorOptions();  // as bench_generator
    GeneratorNet net(o, bench::TwoParts16());
    net->eval();
    const FusedGenerator fused(*net);
    const int64_t k = 50;
    const torch::Tensor h = torch::randn({1, o.t_his, o.num_nodes, 3});
    const torch::Tensor z0 = torch::randn({k, o.nz}), z1 = torch::randn({k, o.nz});
    std::vector<float> out(static_cast<size_t>(k) * o.t_pred * o.num_nodes * 3);
    auto run_fused = [&] {
      fused.Predict(h.data_ptr<float>(), 1, k, {z0.data_ptr<float>(), z1.data_ptr<float>()}, {},
                    out.data());
    };
    auto run_net = [&] {
      torch::NoGradGuard no_grad;
      net->forward(h, {z0, z1});
    };
    AB("generator, 50 futures of 1 history (Human3.6M sizes)",
       {{"FusedGenerator, AVX-512 kernels", run_fused},
        {"FusedGenerator, portable kernels", run_fused, true},
        {"LibTorch GeneratorNet", run_net}},
       rounds_or(41));
  }
  return 0;
}
