#include "generator/inference/forecaster.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "generator/inference/fused_generator.h"
#include "generator/inference/pose_repair.h"
#include "generator/kernels/backend.h"
#include "generator/model/generator_net.h"
#include "generator/model/latents.h"

namespace motionfork {

struct Forecaster::Impl {
  ModelConfig config;
  std::shared_ptr<const Skeleton> skeleton;
  PartPlan parts;
  GeneratorNet net{nullptr};
  // The fused inference path: the same futures as `net` up to float rounding, 1.2-1.6x faster
  // with the AVX-512 kernels (bench_generator, BENCHMARKS.md). Used where the AVX-512 backend
  // runs; on other CPUs its portable backend is 3-4x slower than `net` (bench_generator,
  // 2026-12-02), so `net` runs there. MOTIONFORK_FAST_GENERATOR=0 turns it off, =1 on whatever the
  // backend.
  std::unique_ptr<FusedGenerator> fused;
  std::unique_ptr<PoseRepair> repair;      // when constructed with constraints
  Precision precision = Precision::kFp32;  // resolved: kFp32 or kBf16

  void UsePrecision(Precision resolved) {
    const char* fast_env = std::getenv("MOTIONFORK_FAST_GENERATOR");
    const std::string fast = fast_env ? fast_env : "";
    const bool bf16 = resolved == Precision::kBf16;
    fused.reset();
    if (bf16 || fast == "1" ||
        (fast != "0" && kernels::ActiveBackend() == kernels::Backend::kAvx512))
      fused = std::make_unique<FusedGenerator>(
          *net, bf16 ? ProductPrecision::kBf16 : ProductPrecision::kFp32);
    precision = resolved;
  }
};

Forecaster::Forecaster(ModelConfig config, std::shared_ptr<GeneratorNetImpl> net,
                       std::optional<ConstraintSetSpec> constraints)
    : impl_(std::make_unique<Impl>()) {
  if (!net) throw std::invalid_argument("Forecaster: expected a network, got none");
  Impl& impl = *impl_;
  impl.config = std::move(config);
  impl.net = GeneratorNet(std::move(net));
  impl.net->eval();
  impl.UsePrecision(Precision::kFp32);
  impl.skeleton = std::make_shared<const Skeleton>(Skeleton::Build(impl.config.skeleton));
  impl.parts = MakePartPlan(*impl.skeleton, impl.config.generator.partition);
  if (constraints) {
    impl.repair = std::make_unique<PoseRepair>(*constraints, *impl.skeleton, impl.parts);
  }
}

Forecaster::~Forecaster() = default;
Forecaster::Forecaster(Forecaster&&) noexcept = default;
Forecaster& Forecaster::operator=(Forecaster&&) noexcept = default;

const ModelConfig& Forecaster::config() const { return impl_->config; }

void Forecaster::SetPrecision(Precision p) {
  const Precision resolved = ResolvePrecision(p);
  if (resolved != impl_->precision) impl_->UsePrecision(resolved);
}
Precision Forecaster::precision() const { return impl_->precision; }
void ValidateForecastRequest(const ForecastRequest& request) {
  if (request.k < 1 || request.k > kMaxFutures) {
    throw std::invalid_argument("expected 1.." + std::to_string(kMaxFutures) +
                                " futures per history (k), got " + std::to_string(request.k));
  }
}

const std::shared_ptr<const Skeleton>& Forecaster::skeleton() const { return impl_->skeleton; }
const PartPlan& Forecaster::parts() const { return impl_->parts; }
bool Forecaster::repairs() const { return impl_->repair != nullptr; }

std::vector<float> Forecaster::PredictRootRelative(const std::vector<float>& histories,
                                                   int num_histories,
                                                   const ForecastRequest& request) const {
  const GeneratorOptions& g = impl_->config.generator;
  const int64_t N = g.num_nodes;
  ValidateForecastRequest(request);
  if (num_histories < 1 ||
      histories.size() != static_cast<size_t>(num_histories) * g.t_his * N * 3) {
    throw std::invalid_argument("Predict: expected histories [" + std::to_string(num_histories) +
                                ", " + std::to_string(g.t_his) + ", " + std::to_string(N) +
                                ", 3], got " + std::to_string(histories.size()) + " values");
  }
  for (float v : histories) {
    if (!std::isfinite(v)) throw std::invalid_argument("Predict: the history holds NaN or Inf");
  }
  const std::vector<bool> fixed = impl_->parts.FixedMask(request.fixed_parts);
  torch::NoGradGuard no_grad;
  at::Generator gen = MakeGenerator(request.seed);
  const torch::Tensor h =
      torch::from_blob(const_cast<float*>(histories.data()), {num_histories, g.t_his, N, 3})
          .clone();
  const auto z = SampleLatents(num_histories, request.k, g.nz, fixed, gen);
  // Histories in chunks of about kChunkSamples samples: the activations of a chunk stay in the
  // core's cache (16 x 50 samples at once ran 1.5x slower per history than one history at a
  // time). Each sample's future does not depend on the chunking (batch norm uses its running
  // statistics at inference), and the latents are drawn for all histories first.
  constexpr int64_t kChunkSamples = 64;
  const int64_t chunk = std::max<int64_t>(1, kChunkSamples / request.k);
  torch::Tensor y;  // [Bh*K, t_pred, N, 3]
  if (impl_->fused) {
    // Chunks in parallel on the threads LibTorch was given (each writes its own rows).
    y = torch::empty({static_cast<int64_t>(num_histories) * request.k, g.t_pred, N, 3});
    std::vector<torch::Tensor> zc;
    for (const torch::Tensor& zp : z) zc.push_back(zp.contiguous());
    const int64_t chunks = (num_histories + chunk - 1) / chunk;
    at::parallel_for(0, chunks, 1, [&](int64_t begin, int64_t end) {
      for (int64_t c = begin; c < end; ++c) {
        const int64_t first = c * chunk, n = std::min<int64_t>(chunk, num_histories - first);
        std::vector<const float*> zptr;
        for (const torch::Tensor& zp : zc)
          zptr.push_back(zp.data_ptr<float>() + first * request.k * g.nz);
        impl_->fused->Predict(h.data_ptr<float>() + first * g.t_his * N * 3, n, request.k, zptr,
                              fixed, y.data_ptr<float>() + first * request.k * g.t_pred * N * 3);
      }
    });
  } else {
    std::vector<torch::Tensor> parts_out;
    for (int64_t first = 0; first < num_histories; first += chunk) {
      const int64_t n = std::min<int64_t>(chunk, num_histories - first);
      std::vector<torch::Tensor> zc;
      for (const torch::Tensor& zp : z)
        zc.push_back(zp.slice(0, first * request.k, (first + n) * request.k));
      parts_out.push_back(
          impl_->net->forward(h.slice(0, first, first + n), zc, fixed).slice(1, g.t_his));
    }
    y = (parts_out.size() == 1 ? parts_out[0] : torch::cat(parts_out, 0)).contiguous();
  }
  if (request.repair && impl_->repair) {
    // Root back at the origin for the angle ranges, then repaired, then without it again.
    torch::Tensor poses =
        torch::cat({torch::zeros({y.size(0) * g.t_pred, 1, 3}), y.view({-1, N, 3})}, 1);
    // Each pose's reference layout: its history's last frame.
    const torch::Tensor last = h.select(1, g.t_his - 1);  // [Bh, N, 3]
    const torch::Tensor templates =
        torch::cat({torch::zeros({num_histories, 1, 3}), last}, 1)
            .repeat_interleave(static_cast<int64_t>(request.k) * g.t_pred, 0)
            .contiguous();
    impl_->repair->Repair(poses, templates, fixed);
    y = poses.slice(1, 1).contiguous();
  }
  return std::vector<float>(y.data_ptr<float>(), y.data_ptr<float>() + y.numel());
}

std::vector<float> Forecaster::PredictWorld(const float* history,
                                            const ForecastRequest& request) const {
  const GeneratorOptions& g = impl_->config.generator;
  const int J = g.num_nodes + 1;
  std::vector<float> rel(static_cast<size_t>(g.t_his) * (J - 1) * 3);
  for (int t = 0; t < g.t_his; ++t) {
    const float* fr = history + static_cast<size_t>(t) * J * 3;
    for (int j = 1; j < J; ++j)
      for (int a = 0; a < 3; ++a)
        rel[(static_cast<size_t>(t) * (J - 1) + j - 1) * 3 + a] = fr[3 * j + a] - fr[a];
  }
  const std::vector<float> y = PredictRootRelative(rel, 1, request);
  const float* root = history + static_cast<size_t>(g.t_his - 1) * J * 3;
  std::vector<float> futures(static_cast<size_t>(request.k) * g.t_pred * J * 3);
  for (size_t s = 0; s < static_cast<size_t>(request.k) * g.t_pred; ++s) {
    float* out = &futures[s * J * 3];
    const float* in = &y[s * (J - 1) * 3];
    for (int a = 0; a < 3; ++a) out[a] = root[a];
    for (int j = 1; j < J; ++j)
      for (int a = 0; a < 3; ++a) out[3 * j + a] = root[a] + in[3 * (j - 1) + a];
  }
  return futures;
}

Forecast Forecaster::Predict(const Motion& history, int start,
                             const ForecastRequest& request) const {
  const GeneratorOptions& g = impl_->config.generator;
  const Skeleton& want = *impl_->skeleton;
  if (!history.skeleton().SameStructure(want)) {
    throw std::invalid_argument("Predict: the history's skeleton '" + history.skeleton().name() +
                                "' differs from the model's '" + want.name() +
                                "' (joint names or parents); map it with --skeleton");
  }
  if (std::abs(history.fps() - impl_->config.fps) > 1e-6 * impl_->config.fps) {
    throw std::invalid_argument("Predict: the history is at " + std::to_string(history.fps()) +
                                " Hz, the model at " + std::to_string(impl_->config.fps) +
                                " Hz; resample it");
  }
  if (start < 0 || start + g.t_his > history.num_frames()) {
    throw std::invalid_argument("Predict: the model needs " + std::to_string(g.t_his) +
                                " history frames from frame " + std::to_string(start) +
                                ", the motion has " + std::to_string(history.num_frames()) +
                                " frames");
  }
  const int J = want.num_joints();
  Forecast f;
  f.k = request.k;
  f.t_his = g.t_his;
  f.t_pred = g.t_pred;
  f.joints = J;
  f.fps = history.fps();
  for (int t = start; t < start + g.t_his; ++t) {
    const float* fr = history.frame(t);
    f.history.insert(f.history.end(), fr, fr + J * 3);
  }
  f.futures = PredictWorld(f.history.data(), request);
  return f;
}

}  // namespace motionfork
