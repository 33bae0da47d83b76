// Benchmark: the generator's [M, 256] x [256, 256] matrix products, the panel kernel of
// kernels/panel_product.h against LibTorch's product (OpenBLAS), one thread, in one process, the
// two alternating so that both see the same state of the machine.
//
//   bench_products [--reps R]
//
// Shapes: M = 800 (50 futures x 16 nodes, inference), M = 25,600 (16 histories x 100 futures x
// 16 nodes, a training step's hidden layer). Prints the median and the best of R runs of each, in
// ms and GFLOP/s, and for training the forward + backward of WeightProduct (x W, g W^T by the
// kernel, x^T g by LibTorch) against LibTorch's mm with autograd.
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <vector>

#include "fma_peak.h"
#include "generator/kernels/backend.h"
#include "generator/kernels/panel_product.h"
#include "generator/model/fused_ops.h"
#include "torch_util/blas_core.h"
#include "torch_util/malloc_tuning.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

double Seconds(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Timing {
  std::vector<double> runs;
  double Median() {
    std::sort(runs.begin(), runs.end());
    return runs[runs.size() / 2];
  }
  double Best() { return *std::min_element(runs.begin(), runs.end()); }
};

void Print(const char* what, Timing& t, double gflop) {
  const double median = t.Median(), best = t.Best();
  std::printf("  %-44s %8.2f ms median (%5.1f GFLOP/s), best %8.2f ms (%5.1f GFLOP/s)\n", what,
              median * 1e3, gflop / median, best * 1e3, gflop / best);
}

}  // namespace

int main(int argc, char** argv) {
  UseFastBlasKernels(argv);
  KeepFreedMemory();
  int reps = 0;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) reps = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--help")) {
      std::printf("bench_products [--reps R]: panel kernel vs LibTorch's product, one thread\n");
      return 0;
    }
  }
  if (kernels::ActiveBackend() != kernels::Backend::kAvx512) {
    std::printf("this CPU has no AVX-512: the panel kernel is not used here\n");
    return 0;
  }
  PinThreads(1);
  torch::manual_seed(0);
  bench::PeakGflops(20000000);
  std::printf("AVX-512 multiply-add peak now: %.1f GFLOP/s\n", bench::PeakGflops(100000000));
  const int64_t K = 256, H = 256;
  const torch::Tensor w = torch::randn({K, H});
  const kernels::PackedWeight packed = kernels::PackWeight(w.data_ptr<float>(), K, H);
  for (const int64_t M : {int64_t{800}, int64_t{25600}}) {
    const int runs = reps > 0 ? reps : (M < 1000 ? 400 : 15);
    const double gflop = 2.0 * M * K * H / 1e9;
    const torch::Tensor x = torch::randn({M, K});
    torch::Tensor z = torch::empty({M, H}), zt = torch::empty({M, H});
    Timing kernel, blas;
    for (int r = 0; r < runs; ++r) {
      kernel.runs.push_back(Seconds(
          [&] { kernels::MatMul(x.data_ptr<float>(), M, K, packed, z.data_ptr<float>()); }));
      blas.runs.push_back(Seconds([&] { at::mm_out(zt, x, w); }));
    }
    std::printf("[%lld, 256] x [256, 256], %d runs each (%.2f GFLOP), max |difference| %.2g:\n",
                static_cast<long long>(M), runs, gflop, (z - zt).abs().max().item<double>());
    Print("panel kernel (weights packed once)", kernel, gflop);
    Print("LibTorch mm into a preallocated output", blas, gflop);
    if (M < 1000) continue;
    // Training: forward and backward through autograd, as GraphConv runs them.
    Timing fused, plain;
    const torch::Tensor g = torch::randn({M, H});
    for (int r = 0; r < runs; ++r) {
      fused.runs.push_back(Seconds([&] {
        torch::Tensor xi = x.detach().requires_grad_(true), wi = w.detach().requires_grad_(true);
        WeightProduct(xi, wi).backward(g);
      }));
      plain.runs.push_back(Seconds([&] {
        torch::Tensor xi = x.detach().requires_grad_(true), wi = w.detach().requires_grad_(true);
        xi.mm(wi).backward(g);
      }));
    }
    Print("WeightProduct forward + backward (3 products)", fused, 3 * gflop);
    Print("LibTorch mm forward + backward (3 products)", plain, 3 * gflop);
  }
  return 0;
}
