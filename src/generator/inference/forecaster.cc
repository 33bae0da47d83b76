#include "generator/inference/forecaster.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "core/heading.h"
#include "generator/inference/fused_generator.h"
#include "generator/inference/pose_repair.h"
#include "generator/kernels/backend.h"
#include "generator/model/generator_net.h"
#include "generator/model/latents.h"
#include "generator/trajectory/trajectory_net.h"

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
  // Set: histories are turned into the body's frame before the network sees them.
  struct BodyFrame {
    UpAxis up;
    HeadingJoints nodes;  // the heading's joints as node indices (joint - 1)
  };
  std::optional<BodyFrame> body_frame;
  std::shared_ptr<TrajectoryNetImpl> trajectory;  // set: futures move (AttachTrajectory)
  int trajectory_part = -1;                       // the part whose future the trajectory reads

  // Each future's root, [K, t_pred, 3] relative to the last history root, from the history
  // [t_his, N, 3] and root history [t_his, 3] (relative to the last root) and the futures
  // [K, t_pred, N, 3], all in the body's frame. A fixed trajectory part: one trajectory for all.
  std::vector<float> Trajectories(const float* history, const float* root_history,
                                  const std::vector<float>& futures, int k,
                                  const std::vector<bool>& fixed) const;

  // Turns a root-relative history [t_his, N, 3] into the body's frame of its last frame; returns
  // the turn (core/heading.h).
  double TurnToBodyFrame(float* history) const {
    const GeneratorOptions& g = config.generator;
    return motionfork::TurnToBodyFrame(history, g.t_his, g.num_nodes, g.t_his, body_frame->nodes,
                                       body_frame->up);
  }

  // The network on root-relative histories [Bh, t_his, N, 3] -> [Bh, K, t_pred, N, 3], repaired
  // when asked; arguments validated.
  std::vector<float> Run(const float* histories, int num_histories, const ForecastRequest& request);

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
  if (!impl.config.generator.body_frame.empty()) {
    const UpAxis up = ParseUp(impl.config.generator.body_frame);
    impl.body_frame = Impl::BodyFrame{up, HeadingNodes(*impl.skeleton)};
  }
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

void Forecaster::AttachTrajectory(std::shared_ptr<TrajectoryNetImpl> trajectory) {
  if (!trajectory) throw std::invalid_argument("trajectory: expected a network, got none");
  const GeneratorOptions& g = impl_->config.generator;
  const TrajectoryOptions& o = trajectory->options();
  if (!impl_->body_frame) {
    throw std::invalid_argument(
        "trajectory: the generator predicts in the data's axes; a trajectory needs one trained in "
        "the body's frame (generator.body_frame: true)");
  }
  const UpAxis up = ParseUp(o.up);
  if (o.t_his != g.t_his || o.t_pred != g.t_pred || o.num_nodes != g.num_nodes ||
      up.axis != impl_->body_frame->up.axis || up.sign != impl_->body_frame->up.sign) {
    throw std::invalid_argument("trajectory: made for t_his " + std::to_string(o.t_his) +
                                ", t_pred " + std::to_string(o.t_pred) + ", " +
                                std::to_string(o.num_nodes) + " nodes, up " + o.up +
                                "; the generator has t_his " + std::to_string(g.t_his) +
                                ", t_pred " + std::to_string(g.t_pred) + ", " +
                                std::to_string(g.num_nodes) + " nodes, up " + g.body_frame);
  }
  int part = -1;
  for (int p = 0; p < impl_->parts.num_parts(); ++p) {
    const auto& nodes = impl_->parts.nodes[p];
    if (!o.future_nodes.empty() &&
        std::all_of(o.future_nodes.begin(), o.future_nodes.end(), [&](int64_t n) {
          return std::find(nodes.begin(), nodes.end(), n) != nodes.end();
        }))
      part = p;
  }
  trajectory->eval();
  impl_->trajectory = std::move(trajectory);
  impl_->trajectory_part = part;
}

bool Forecaster::moves_root() const { return impl_->trajectory != nullptr; }

std::optional<UpAxis> Forecaster::body_frame() const {
  if (!impl_->body_frame) return std::nullopt;
  return impl_->body_frame->up;
}

namespace {

// Throws std::invalid_argument when a history value is NaN or Inf.
void RequireFinite(const std::vector<float>& history) {
  for (float v : history) {
    if (!std::isfinite(v)) throw std::invalid_argument("Predict: the history holds NaN or Inf");
  }
}

}  // namespace

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
  RequireFinite(histories);
  if (!impl_->body_frame) return impl_->Run(histories.data(), num_histories, request);
  // In the body's frame: each history turned so that its last frame faces the same way, its
  // futures turned back.
  std::vector<float> turned = histories;
  std::vector<double> angles(num_histories);
  const size_t his = static_cast<size_t>(g.t_his) * N;
  for (int b = 0; b < num_histories; ++b) angles[b] = impl_->TurnToBodyFrame(&turned[b * his * 3]);
  std::vector<float> y = impl_->Run(turned.data(), num_histories, request);
  const size_t fut = static_cast<size_t>(request.k) * g.t_pred * N;
  for (int b = 0; b < num_histories; ++b)
    RotateAboutUp(&y[b * fut * 3], fut, -angles[b], impl_->body_frame->up);
  return y;
}

std::vector<float> Forecaster::Impl::Run(const float* histories, int num_histories,
                                         const ForecastRequest& request) {
  const GeneratorOptions& g = config.generator;
  const int64_t N = g.num_nodes;
  const std::vector<bool> fixed = parts.FixedMask(request.fixed_parts);
  torch::NoGradGuard no_grad;
  at::Generator gen = MakeGenerator(request.seed);
  const torch::Tensor h =
      torch::from_blob(const_cast<float*>(histories), {num_histories, g.t_his, N, 3}).clone();
  const auto z = SampleLatents(num_histories, request.k, g.nz, fixed, gen);
  // Histories in chunks of about kChunkSamples samples: the activations of a chunk stay in the
  // core's cache (16 x 50 samples at once ran 1.5x slower per history than one history at a
  // time). Each sample's future does not depend on the chunking (batch norm uses its running
  // statistics at inference), and the latents are drawn for all histories first.
  constexpr int64_t kChunkSamples = 64;
  const int64_t chunk = std::max<int64_t>(1, kChunkSamples / request.k);
  torch::Tensor y;  // [Bh*K, t_pred, N, 3]
  if (fused) {
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
        fused->Predict(h.data_ptr<float>() + first * g.t_his * N * 3, n, request.k, zptr, fixed,
                       y.data_ptr<float>() + first * request.k * g.t_pred * N * 3);
      }
    });
  } else {
    std::vector<torch::Tensor> parts_out;
    for (int64_t first = 0; first < num_histories; first += chunk) {
      const int64_t n = std::min<int64_t>(chunk, num_histories - first);
      std::vector<torch::Tensor> zc;
      for (const torch::Tensor& zp : z)
        zc.push_back(zp.slice(0, first * request.k, (first + n) * request.k));
      parts_out.push_back(net->forward(h.slice(0, first, first + n), zc, fixed).slice(1, g.t_his));
    }
    y = (parts_out.size() == 1 ? parts_out[0] : torch::cat(parts_out, 0)).contiguous();
  }
  if (request.repair && repair) {
    // Root back at the origin for the angle ranges, then repaired, then without it again.
    torch::Tensor poses =
        torch::cat({torch::zeros({y.size(0) * g.t_pred, 1, 3}), y.view({-1, N, 3})}, 1);
    // Each pose's reference layout: its history's last frame.
    const torch::Tensor last = h.select(1, g.t_his - 1);  // [Bh, N, 3]
    const torch::Tensor templates =
        torch::cat({torch::zeros({num_histories, 1, 3}), last}, 1)
            .repeat_interleave(static_cast<int64_t>(request.k) * g.t_pred, 0)
            .contiguous();
    repair->Repair(poses, templates, fixed);
    y = poses.slice(1, 1).contiguous();
  }
  return std::vector<float>(y.data_ptr<float>(), y.data_ptr<float>() + y.numel());
}

std::vector<float> Forecaster::Impl::Trajectories(const float* history, const float* root_history,
                                                  const std::vector<float>& futures, int k,
                                                  const std::vector<bool>& fixed) const {
  const GeneratorOptions& g = config.generator;
  const int64_t N = g.num_nodes;
  const bool one = trajectory_part >= 0 && trajectory_part < static_cast<int>(fixed.size()) &&
                   fixed[trajectory_part];
  const int64_t rows = one ? 1 : k;
  torch::NoGradGuard no_grad;
  const torch::Tensor his =
      torch::from_blob(const_cast<float*>(history), {1, g.t_his, N, 3}).expand({rows, -1, -1, -1});
  const torch::Tensor fut =
      torch::from_blob(const_cast<float*>(futures.data()), {k, g.t_pred, N, 3}).slice(0, 0, rows);
  const torch::Tensor root =
      torch::from_blob(const_cast<float*>(root_history), {1, g.t_his, 3}).expand({rows, -1, -1});
  const torch::Tensor y = trajectory->forward(torch::cat({his, fut}, 1), root).contiguous();
  std::vector<float> out(static_cast<size_t>(k) * g.t_pred * 3);
  const size_t per = static_cast<size_t>(g.t_pred) * 3;
  for (int s = 0; s < k; ++s)
    std::copy(y.data_ptr<float>() + (one ? 0 : s) * per,
              y.data_ptr<float>() + (one ? 1 : s + 1) * per, out.begin() + s * per);
  return out;
}

std::vector<float> Forecaster::PredictWorld(const float* history,
                                            const ForecastRequest& request) const {
  const GeneratorOptions& g = impl_->config.generator;
  const int J = g.num_nodes + 1;
  std::vector<float> rel(static_cast<size_t>(g.t_his) * (J - 1) * 3);
  const float* root = history + static_cast<size_t>(g.t_his - 1) * J * 3;
  std::vector<float> root_history(static_cast<size_t>(g.t_his) * 3);
  for (int t = 0; t < g.t_his; ++t) {
    const float* fr = history + static_cast<size_t>(t) * J * 3;
    for (int a = 0; a < 3; ++a) root_history[3 * t + a] = fr[a] - root[a];
    for (int j = 1; j < J; ++j)
      for (int a = 0; a < 3; ++a)
        rel[(static_cast<size_t>(t) * (J - 1) + j - 1) * 3 + a] = fr[3 * j + a] - fr[a];
  }
  std::vector<float> y, path;  // futures [K, t_pred, N, 3]; their roots [K, t_pred, 3]
  const size_t steps = static_cast<size_t>(request.k) * g.t_pred;
  if (impl_->trajectory) {
    // In the body's frame: the network and the trajectory see the history turned, their futures
    // are turned back.
    ValidateForecastRequest(request);
    RequireFinite(rel);
    const UpAxis up = impl_->body_frame->up;
    const double turn = impl_->TurnToBodyFrame(rel.data());
    RotateAboutUp(root_history.data(), g.t_his, turn, up);
    y = impl_->Run(rel.data(), 1, request);
    path = impl_->Trajectories(rel.data(), root_history.data(), y, request.k,
                               impl_->parts.FixedMask(request.fixed_parts));
    RotateAboutUp(y.data(), steps * (J - 1), -turn, up);
    RotateAboutUp(path.data(), steps, -turn, up);
  } else {
    y = PredictRootRelative(rel, 1, request);
    path.assign(steps * 3, 0.0f);
  }
  std::vector<float> futures(steps * J * 3);
  for (size_t s = 0; s < steps; ++s) {
    float* out = &futures[s * J * 3];
    const float* in = &y[s * (J - 1) * 3];
    for (int a = 0; a < 3; ++a) out[a] = root[a] + path[3 * s + a];
    for (int j = 1; j < J; ++j)
      for (int a = 0; a < 3; ++a) out[3 * j + a] = out[a] + in[3 * (j - 1) + a];
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
  f.root_moves = moves_root();
  return f;
}

}  // namespace motionfork
