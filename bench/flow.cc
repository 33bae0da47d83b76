// Benchmark: the pose prior (GSPS flow on limb directions, 48 numbers, 3 layers), one thread.
//
//   bench_flow [--threads N] [--reps N] [--glibc-default]
//
// Prints medians of:
//   1. log_prob of 4,096 poses (inference): Q built once per call as a 48 x 48 matrix and applied
//      as one product (ours), vs the original's way (every Householder reflection applied to every
//      pose, same network, same LibTorch);
//   2. a training step at batch 4,096 (forward, backward, Adam), ours vs the original's way;
//   3. the prior inside a generator training step: NLL of 54,400 predicted poses (positions ->
//      limb directions -> log_prob), forward and backward to the poses, parameters frozen; with
//      the memory the autograd graph holds between forward and backward (glibc's mallinfo2).
// The figures for the original PyTorch code on this machine type (one thread): 41 ms,
// 213 ms, and 1.27 s forward for the 54,400 poses.
#include <malloc.h>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <vector>

#include "flow/flow_module.h"
#include "torch_util/blas_core.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

// Bytes currently allocated through malloc (small blocks + mmapped large ones), glibc.
double HeapMb() {
  const struct mallinfo2 m = mallinfo2();
  return (static_cast<double>(m.uordblks) + static_cast<double>(m.hblkhd)) / 1e6;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double TimeMs(const std::function<void()>& f, int reps) {
  f();  // warm-up
  std::vector<double> ms;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return Median(ms);
}

// The original code's way: every Householder reflection applied to the whole batch in turn, then
// R, the bias and the PReLU (the same function as ours; what it costs is the point).
std::pair<torch::Tensor, torch::Tensor> OriginalForward(const PoseFlow& flow,
                                                        const torch::Tensor& x) {
  torch::Tensor y = x;
  torch::Tensor log_det = torch::zeros({x.size(0)});
  for (int l = 0; l < flow->num_layers(); ++l) {
    const auto& layer = flow->layer(l);
    for (int k = 0; k < layer->num_reflections(); ++k) {  // y <- y H_k, H_k = I - 2 u u^T
      const torch::Tensor v = layer->reflections[k];
      const torch::Tensor u = v / v.norm();
      y = y - 2 * y.mv(u).unsqueeze(1) * u.unsqueeze(0);
    }
    y = y.mm(layer->Triangular().to(torch::kFloat32)) + layer->bias;
    log_det = log_det + layer->r_log_diag.sum();
    if (l + 1 < flow->num_layers()) {
      const torch::Tensor a = flow->prelu_log_slope(l);
      log_det = log_det + y.lt(0).sum(1).to(torch::kFloat32) * a;
      y = torch::prelu(y, a.exp());
    }
  }
  return {y, log_det};
}

torch::Tensor OriginalLogProb(const PoseFlow& flow, const torch::Tensor& x) {
  const auto [z, ld] = OriginalForward(flow, x);
  return ld - 0.5 * z.square().sum(1) - 0.5 * 1.8378770664093453 * x.size(1);
}

}  // namespace

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  int threads = 1, reps = 200;
  bool glibc_default = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--glibc-default")) glibc_default = true;
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) reps = std::atoi(argv[++i]);
  }
  PinThreads(threads);
  // As the prior commands do (apps/motionfork/cmd_prior.cc): without it glibc returns every freed
  // tensor to the kernel and each new one pays page faults (log_prob 5.6 ms instead of 1.7 ms).
  // --glibc-default measures that.
  if (!glibc_default) {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
  }
  const int D = 48;
  PoseFlow flow(D, FlowOptions{});
  flow->Initialize(0);
  std::printf("prior: 3 layers, 48 reflections each, %lld parameters, %d thread(s), %s\n",
              static_cast<long long>(flow->NumParameters()), threads,
              glibc_default ? "glibc's default malloc trimming" : "freed memory kept (mallopt)");
  torch::manual_seed(0);
  torch::Tensor x = torch::randn({4096, 16, 3});
  x = (x / x.norm(2, -1, true)).reshape({4096, D});

  {
    c10::InferenceMode guard;
    const double ours = TimeMs([&] { flow->log_prob(x); }, reps);
    const double orig = TimeMs([&] { OriginalLogProb(flow, x); }, std::max(10, reps / 10));
    const double diff = (flow->log_prob(x) - OriginalLogProb(flow, x)).abs().max().item<double>();
    std::printf(
        "log_prob, 4,096 poses:        %8.3f ms  (original's way in LibTorch: %.2f ms, "
        "%.1fx; issue's PyTorch figure 41 ms; max |difference| %.1e)\n",
        ours, orig, orig / ours, diff);
  }
  {
    auto step_with = [&](auto&& log_prob) {
      PoseFlow f(D, FlowOptions{});
      f->Initialize(0);
      torch::optim::Adam adam(f->parameters(), torch::optim::AdamOptions(1e-2).weight_decay(1e-3));
      return TimeMs(
          [&] {
            const torch::Tensor loss = -log_prob(f, x).mean();
            adam.zero_grad();
            loss.backward();
            adam.step();
          },
          std::max(10, reps / 4));
    };
    const double ours =
        step_with([](const PoseFlow& f, const torch::Tensor& b) { return f->log_prob(b); });
    const double orig =
        step_with([](const PoseFlow& f, const torch::Tensor& b) { return OriginalLogProb(f, b); });
    std::printf(
        "training step, batch 4,096:   %8.3f ms  (original's way in LibTorch: %.2f ms, "
        "%.1fx; issue's PyTorch figure 213 ms)\n",
        ours, orig, orig / ours);
  }
  {
    // Inside the generator: 54,400 predicted poses (16 histories x 100 futures x
    // every 3rd of 100 frames + offsets, as in GSPS's H36M step), prior frozen.
    flow->Freeze();
    const std::vector<int> parents = {-1, 0, 1, 2, 0, 4, 5, 0, 7, 8, 9, 8, 11, 12, 8, 14, 15};
    // Root-relative, root omitted (the generator's layout): [54400, 16, 3].
    torch::Tensor pos = torch::randn({54400, 16, 3}).requires_grad_(true);
    std::vector<double> f_all, b_all;
    double graph_mb = 0;
    for (int r = 0; r < std::max(5, reps / 20) + 1; ++r) {
      const double heap0 = HeapMb();
      const auto t0 = std::chrono::steady_clock::now();
      const torch::Tensor nll = -flow->log_prob(LimbDirectionsRootRelative(pos, parents)).mean();
      const auto t1 = std::chrono::steady_clock::now();
      graph_mb = std::max(graph_mb, HeapMb() - heap0);  // what the graph keeps for backward
      nll.backward();
      const auto t2 = std::chrono::steady_clock::now();
      pos.mutable_grad().reset();
      if (r == 0) continue;  // warm-up
      f_all.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      b_all.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    }
    std::printf(
        "generator step, 54,400 poses: %8.3f ms forward + %.3f ms backward to the poses "
        "(issue: 1.27 s forward); the graph holds %.0f MB (poses: %.0f MB)\n",
        Median(f_all), Median(b_all), graph_mb, 54400.0 * 48 * 4 / 1e6);
  }
  return 0;
}
