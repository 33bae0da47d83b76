// Benchmark: one GSPS training step with every loss, at the Human3.6M sizes, one thread.
//
//   bench_generator_training [--threads N] [--steps S] [--warmup W] [--precision fp32|bf16|ab]
//                            [--reference bench/reference_gsps_training.py]
//
// --precision bf16: the residual blocks' products (forward and backward) with bf16 inputs and
// float32 sums (training.precision, issue 30; needs AVX512-BF16); ab: steps alternate between
// fp32 and bf16 (S steps of each after W warm-up steps of each), and the ratio of the medians is
// printed: the A/B comparison within one run.
//
// 16 histories x 100 futures (10 x 10 nested samples per part), 16 nodes, t_his 25, t_pred 100,
// n_pre 10, hidden 256, 4 blocks, nz 64, two parts (the h36m skeleton's default partition); the
// losses of training: past reconstruction, limb lengths, diversity per part, best-of-many,
// best-of-many against 10 pseudo multimodal futures, the flow-prior NLL (configs/models/
// flow_prior.yaml sizes, untrained: the cost does not depend on the weights) on every 3rd
// predicted frame, the angle penalty (configs/constraints/h36m.yaml). Synthetic inputs: the time
// does not depend on the values. Prints each step's time and page faults, each phase's median over
// the steps after the warm-up and the peak memory. The first steps fault in the heap (3.4 GB,
// about 18 us of kernel time per page on this VM) and are not what a long training run sees: W
// (default 3) warm-up steps are left out of the medians.
// --reference SCRIPT: GSPS's own training step in PyTorch (bench/reference_gsps_training.py, in its
// own process on the same threads; /usr/bin/python3 or $MOTIONFORK_PYTHON) timed in turns with
// ours, one reference step after each of ours (after each fp32 / bf16 pair with ab), and the
// ratio of the medians printed: the "training step N x faster than the reference" figure.
// MOTIONFORK_PROFILE=FILE writes LibTorch's profile of the last step (a Chrome trace) to FILE.
#include <sys/resource.h>
#include <torch/csrc/autograd/profiler_legacy.h>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bodyparts/part_plan.h"
#include "bundle/prior_bundle.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "constraints/torch/angle_penalty.h"
#include "flow/flow_module.h"
#include "flow/pose_prior.h"
#include "fma_peak.h"
#include "generator/kernels/cpu_features.h"
#include "generator/kernels/precision.h"
#include "generator/model/generator_net.h"
#include "generator/model/latents.h"
#include "generator/training/losses.h"
#include "generator_sizes.h"
#include "peak_memory.h"
#include "reference_process.h"
#include "torch_util/blas_core.h"
#include "torch_util/malloc_tuning.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(const Clock::time_point& t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  UseFastBlasKernels(argv);
  KeepFreedMemory();
  int threads = 1, steps = 3, warmup = 3;
  std::string precision = "fp32", reference_script;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--precision") && i + 1 < argc) precision = argv[++i];
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--reference") && i + 1 < argc) reference_script = argv[++i];
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::max(1, std::atoi(argv[++i]));
    if (!std::strcmp(argv[i], "--warmup") && i + 1 < argc)
      warmup = std::max(0, std::atoi(argv[++i]));
  }
  if (precision != "fp32" && precision != "bf16" && precision != "ab") {
    std::fprintf(stderr, "--precision: expected fp32, bf16 or ab, got '%s'\n", precision.c_str());
    return 2;
  }
  if (precision != "fp32" && !Bf16ProductsAvailable()) {
    std::fprintf(stderr, "--precision %s: no AVX512-BF16 kernel on this CPU or build\n",
                 precision.c_str());
    return 2;
  }
  const bool ab = precision == "ab";
  if (ab) {
    warmup *= 2;
    steps *= 2;
  }
  PinThreads(threads);
  std::unique_ptr<bench::ReferenceProcess> reference;
  if (!reference_script.empty()) {
    // Started (and warmed up) before our network is built: its two warm-up steps fault in its
    // own heap, not ours.
    reference = bench::ReferenceProcess::Python(reference_script, threads);
  }
  torch::manual_seed(0);
  const std::string configs = MOTIONFORK_BENCH_CONFIG_DIR;
  const std::shared_ptr<const Skeleton> skeleton =
      LoadSkeletonConfig(configs + "/skeletons/h36m.yaml").skeleton;
  const PartPlan plan = MakePartPlan(*skeleton, "default");
  const GeneratorOptions o = bench::H36mGeneratorOptions(skeleton->num_joints() - 1);
  GeneratorNet net(o, plan.nodes);
  net->train();
  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(1e-3));

  // The two optional terms, built as `motionfork train` builds them.
  LossHooks hooks;
  double angle_seconds = 0, prior_seconds = 0;  // forward time inside the two hooks, this step
  auto penalty = std::make_shared<AnglePenalty>(
      ConstraintSet::Build(LoadConstraintConfig(configs + "/constraints/h36m.yaml"), *skeleton));
  hooks.angle_penalty = [penalty, &angle_seconds](const torch::Tensor& poses) {
    const auto t0 = Clock::now();
    auto sizes = poses.sizes().vec();
    sizes[sizes.size() - 2] = 1;
    torch::Tensor out = (*penalty)->forward(torch::cat({torch::zeros(sizes), poses}, -2));
    angle_seconds = Seconds(t0);
    return out;
  };
  auto prior =
      std::make_shared<PosePrior>(skeleton, LoadFlowConfig(configs + "/models/flow_prior.yaml"));
  prior->module()->Freeze();
  const std::vector<int> parents = skeleton->parents();
  hooks.prior_nll = [prior, parents, &prior_seconds](const torch::Tensor& poses) {
    const auto t0 = Clock::now();
    torch::Tensor out =
        -prior->module()->log_prob(LimbDirectionsRootRelative(poses, parents)).mean();
    prior_seconds = Seconds(t0);
    return out;
  };
  LossWeights weights;
  weights.diversity = {8, 25};  // GSPS H36M
  weights.diversity_scale = {100, 300};

  const int64_t Bh = 16, M = 10, N = o.num_nodes, T = o.num_frames();
  const std::vector<int64_t> per_part = {10, 10};
  std::vector<int64_t> node_parents(N);
  for (int64_t n = 0; n < N; ++n) node_parents[n] = skeleton->parent(static_cast<int>(n) + 1) - 1;
  at::Generator gen = MakeGenerator(0);
  std::printf("training step: %lld histories x %lld futures, threads: %d, products: %s\n",
              static_cast<long long>(Bh), static_cast<long long>(per_part[0] * per_part[1]),
              threads, ab ? "fp32 and bf16 in turns" : precision.c_str());
  std::vector<double> forward, losses, backward, update, total, prior_time, angle_time;
  std::vector<double> totals[2];  // ab: fp32, bf16
  std::vector<double> reference_steps;
  for (int s = 0; s < warmup + steps; ++s) {
    const bool bf16 = ab ? s % 2 == 1 : precision == "bf16";
    net->set_bf16_products(bf16);
    const torch::Tensor truth = torch::randn({Bh, T, N, 3}) * 0.2;
    const torch::Tensor pseudo = torch::randn({Bh, M, o.t_pred, N, 3}) * 0.2;
    const torch::Tensor mask = torch::ones({Bh, M});
    const auto z = NestedLatents(Bh, per_part, o.nz, gen);
    std::unique_ptr<torch::autograd::profiler::RecordProfile> profile;
    if (s == warmup + steps - 1 && std::getenv("MOTIONFORK_PROFILE")) {
      profile = std::make_unique<torch::autograd::profiler::RecordProfile>(
          std::getenv("MOTIONFORK_PROFILE"));
    }
    rusage ru0;
    getrusage(RUSAGE_SELF, &ru0);
    const auto t0 = Clock::now();
    LossBatch batch{net->ForwardNested(truth.slice(1, 0, o.t_his), z, per_part),
                    truth,
                    pseudo,
                    mask,
                    per_part,
                    plan.nodes,
                    node_parents,
                    o.t_his};
    const double t_forward = Seconds(t0);
    const auto t1 = Clock::now();
    const LossTerms terms = ComputeLosses(batch, weights, hooks, 0, 3);
    const double t_losses = Seconds(t1);
    const auto t2 = Clock::now();
    adam.zero_grad();
    terms.total.backward();
    const double t_backward = Seconds(t2);
    const auto t3 = Clock::now();
    torch::nn::utils::clip_grad_norm_(net->parameters(), 100);
    adam.step();
    const double t_update = Seconds(t3);
    rusage ru1;
    getrusage(RUSAGE_SELF, &ru1);
    std::printf("step %d%s%s: %.2f s, %ld page faults, %.2f s in the kernel\n", s,
                bf16 ? " bf16" : " fp32", s < warmup ? " (warm-up)" : "", Seconds(t0),
                ru1.ru_minflt - ru0.ru_minflt,
                (ru1.ru_stime.tv_sec - ru0.ru_stime.tv_sec) +
                    1e-6 * (ru1.ru_stime.tv_usec - ru0.ru_stime.tv_usec));
    std::fflush(stdout);
    if (s < warmup) continue;
    forward.push_back(t_forward);
    losses.push_back(t_losses);
    prior_time.push_back(prior_seconds);
    angle_time.push_back(angle_seconds);
    backward.push_back(t_backward);
    update.push_back(t_update);
    total.push_back(Seconds(t0));
    totals[bf16].push_back(total.back());
    if (reference && (!ab || bf16)) {
      reference_steps.push_back(reference->Run());
      std::printf("reference step: %.2f s\n", reference_steps.back());
      std::fflush(stdout);
    }
  }
  // Each engine's measured peak and the share of it the step reached: the step's graph-conv
  // products (the forward pass and the two backward products, 3x the forward's multiply-adds)
  // over its time; bf16 steps against the best time the two peaks allow for their split (the
  // residual blocks' products in bf16, the rest float32).
  if (kernels::Cpu().avx512) {
    const double samples = static_cast<double>(Bh) * per_part[0] * per_part[1];
    const double gflop = 3 * 2 * bench::MacsPerSample(o, 2) * samples / 1e9;
    const double peak = bench::PeakGflops(100000000);
    std::printf("products: %.1f GFLOP a step (forward and both backward products)\n", gflop);
    if (!totals[0].empty())
      std::printf("  fp32 step: %.0f%% of the AVX-512 FMA peak (%.1f GFLOP/s)\n",
                  100 * gflop / Median(totals[0]) / peak, peak);
    if (!totals[1].empty()) {
      const double peak16 = bench::PeakBf16Gflops(100000000);
      const double gflop16 = 3 * 2 * bench::HiddenProductMacsPerSample(o, 2) * samples / 1e9;
      const double best = gflop16 / peak16 + (gflop - gflop16) / peak;
      std::printf(
          "  bf16 step: %.0f%% of the best the two peaks allow (vdpbf16ps peak %.1f GFLOP/s, "
          "%.0f%% of the products in bf16)\n",
          100 * best / Median(totals[1]), peak16, 100 * gflop16 / gflop);
    }
  }
  if (ab) {
    const double a = Median(totals[0]), b = Median(totals[1]);
    std::printf("A/B, %zu steps each: fp32 %.3f s, bf16 %.3f s median; bf16 %.2fx fp32's speed\n",
                totals[0].size(), a, b, a / b);
  }
  if (reference) {
    const double r = Median(reference_steps);
    std::printf(
        "reference: GSPS's training step in PyTorch (%s, %lld generator parameters): %.2f "
        "s median of %zu, in turns with ours\n",
        reference_script.c_str(), reference->parameters(), r, reference_steps.size());
    if (ab || precision == "fp32")
      std::printf("  fp32 step %.2fx faster than the reference\n", r / Median(totals[0]));
    if (ab || precision == "bf16")
      std::printf("  bf16 step %.2fx faster than the reference\n", r / Median(totals[1]));
  }
  std::printf("generator forward: %.2f s\n", Median(forward));
  std::printf("losses (incl. prior NLL and angle penalty): %.2f s\n", Median(losses));
  std::printf("  of which prior NLL forward %.2f s, angle penalty forward %.2f s\n",
              Median(prior_time), Median(angle_time));
  std::printf("backward (all terms): %.2f s\n", Median(backward));
  std::printf("clip + Adam: %.3f s\n", Median(update));
  std::printf(
      "training step, all losses: %.2f s median of %d (after %d warm-up steps), fastest %.2f s\n",
      Median(total), steps, warmup, *std::min_element(total.begin(), total.end()));
  std::printf("peak resident memory: %.0f MB\n", bench::PeakResidentMegabytes());
  return 0;
}
