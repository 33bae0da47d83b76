#include "generator/training/training.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <tuple>

#include "bodyparts/part_plan.h"
#include "bundle/generator_net_bundle.h"
#include "core/heading.h"
#include "generator/kernels/precision.h"
#include "generator/model/fused_ops.h"
#include "generator/model/latents.h"
#include "generator/training/augmentation.h"
#include "launch/worker_place.h"
#include "torch_util/checkpoint.h"
#include "torch_util/data_parallel.h"
#include "torch_util/threads.h"
#include "torch_util/training_loop.h"

namespace motionfork {

namespace fs = std::filesystem;

void RetargetFuture(const float* future, const float* reference,
                    const std::vector<int64_t>& parents, int frames, int nodes, float* out) {
  auto vec = [](const float* pose, const std::vector<int64_t>& par, int n, float v[3]) {
    const float* p = pose + 3 * n;
    const float zero[3] = {0, 0, 0};
    const float* q = par[n] < 0 ? zero : pose + 3 * par[n];
    for (int a = 0; a < 3; ++a) v[a] = p[a] - q[a];
  };
  std::vector<float> length(nodes);
  for (int n = 0; n < nodes; ++n) {
    float v[3];
    vec(reference, parents, n, v);
    length[n] = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  for (int t = 0; t < frames; ++t) {
    const float* src = future + static_cast<size_t>(t) * nodes * 3;
    float* dst = out + static_cast<size_t>(t) * nodes * 3;
    for (int n = 0; n < nodes; ++n) {  // parents come before children
      float v[3];
      vec(src, parents, n, v);
      const float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      const float s = len > 1e-8f ? length[n] / len : 0.0f;
      for (int a = 0; a < 3; ++a) {
        dst[3 * n + a] = (parents[n] < 0 ? 0.0f : dst[3 * parents[n] + a]) + s * v[a];
      }
    }
  }
}

namespace {

double LearningRate(const TrainingOptions& t, int epoch) {
  if (epoch < t.lr_constant_epochs) return t.learning_rate;
  const int decay = t.epochs - t.lr_constant_epochs;
  return t.learning_rate *
         (1.0 - static_cast<double>(epoch - t.lr_constant_epochs) / std::max(1, decay));
}

}  // namespace

TrainSummary TrainGenerator(const GeneratorTrainConfig& config, const ModelConfig& model,
                            const TrainingWindows& data, const std::string& out_dir,
                            const LossHooks& hooks, const TrainCallbacks& cb,
                            int stop_after_epochs) {
  const TrainingOptions& t = config.training;
  DataParallel& workers = TrainingWorkers();
  PinThreads(workers.ThreadsPerWorker(t.threads));
  torch::manual_seed(t.seed);
  const Skeleton skeleton = Skeleton::Build(model.skeleton);
  const PartPlan plan = MakePartPlan(skeleton, model.generator.partition);
  if (static_cast<int>(t.samples_per_part.size()) != plan.num_parts()) {
    throw std::invalid_argument("training: samples_per_part has " +
                                std::to_string(t.samples_per_part.size()) +
                                " entries, the partition '" + plan.partition + "' has " +
                                std::to_string(plan.num_parts()) + " parts");
  }
  if (model.generator.body_frame.empty() == data.up.has_value()) {
    throw std::invalid_argument(std::string("training: the generator predicts in ") +
                                (data.up ? "the data's axes" : "the body's frame") +
                                ", its windows were built in " +
                                (data.up ? "the body's frame" : "the data's axes") +
                                " (BuildTrainingWindows's body_frame must be the generator's)");
  }
  const int Bh = t.batch_histories;
  workers.RequireBatch(Bh, "training.batch_histories");
  GeneratorNet net(model.generator, plan.nodes);
  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(t.learning_rate));
  const fs::path out(out_dir), ckpt = out / "checkpoint";
  TrainSummary summary;
  std::vector<double> resumed = {0};
  if (workers.writes())
    resumed[0] = ResumeFromCheckpoint(ckpt, "generator.pt", *net, adam, out / "log.csv");
  workers.BroadcastTrainingState(*net, adam, &resumed);
  summary.first_epoch = static_cast<int>(resumed[0]);
  summary.epochs_done = summary.first_epoch;  // a finished run resumed has them all
  if (summary.first_epoch > 0 && cb.message) {
    cb.message("resuming from " + ckpt.string() + " at epoch " +
               std::to_string(summary.first_epoch + 1));
  }

  const int N = data.num_nodes, T = data.num_frames();
  const int M = config.multimodal.max_per_window;
  const AugmentationOptions& augment = config.augmentation;
  const MirrorPlan mirror = augment.mirror > 0 ? MakeMirrorPlan(skeleton, data) : MirrorPlan{};
  if (augment.mirror > 0 && cb.message && workers.writes()) {
    cb.message("mirroring: left and right exchanged, axis " + std::string(1, "xyz"[mirror.axis]) +
               " reflected (the training windows' hip lines lie along it)");
  }
  // A window (or pseudo window) of `frames` frames as its draw varies it: mirrored, resized.
  auto vary = [&](const WindowAugmentation& a, int frames, float* poses) {
    if (a.mirror) MirrorPoses(mirror, frames, poses);
    if (a.scale != 1) ScalePoses(a.scale, static_cast<size_t>(frames) * N * 3, poses);
  };
  // This worker's share of every step's histories and the weight of its gradients.
  const Share share = workers.BatchShare(Bh);
  const int Bs = static_cast<int>(share.size());
  const double weight = static_cast<double>(Bs) / Bh;
  BatchSync sync{[&workers](std::vector<double>* v) { workers.SumValues(v, "batch statistics"); },
                 weight};
  if (workers.distributed() && t.sync_batch_norm) net->set_batch_sync(&sync);
  // bf16 products where the config asks (an error naming the missing feature where it cannot).
  const bool bf16 = ResolvePrecision(t.precision) == Precision::kBf16;
  net->set_bf16_products(bf16);
  if (bf16 && cb.message && workers.writes())
    cb.message("products:  the residual blocks' in bf16 (AVX512-BF16), float32 sums");
  std::vector<int64_t> node_parents(N);
  for (int n = 0; n < N; ++n) node_parents[n] = skeleton.parent(n + 1) - 1;
  const int iterations = t.windows_per_epoch / Bh;
  const auto start = std::chrono::steady_clock::now();

  for (int epoch = summary.first_epoch; epoch < t.epochs; ++epoch) {
    if (stop_after_epochs > 0 && epoch - summary.first_epoch >= stop_after_epochs) break;
    const auto epoch_start = std::chrono::steady_clock::now();
    const double lr = LearningRate(t, epoch);
    SetLearningRate(adam, lr);
    net->train();
    // Every worker draws the whole step (windows, latents, prior frames) from the same seeded
    // generators and keeps its share, so that the run does not depend on the number of workers.
    std::mt19937_64 rng(t.seed * 1000003ull + epoch);
    at::Generator gen = MakeGenerator(t.seed * 7919ull + epoch);
    std::uniform_int_distribution<int> pick(0, static_cast<int>(data.windows.size()) - 1);
    std::vector<std::pair<std::string, double>> sums;
    std::vector<int> picked(Bh);
    for (int it = 0; it < iterations; ++it) {
      for (int& w : picked) w = pick(rng);
      const std::vector<WindowAugmentation> drawn =
          augment.enabled() ? DrawAugmentations(augment, Bh, rng)
                            : std::vector<WindowAugmentation>(static_cast<size_t>(Bh));
      const uint64_t noise_seed = augment.history_noise > 0 ? rng() : 0;
      torch::Tensor truth = torch::empty({Bs, T, N, 3});
      torch::Tensor pseudo = torch::zeros({Bs, M, data.t_pred, N, 3});
      torch::Tensor mask = torch::zeros({Bs, M});
      std::vector<float> other(static_cast<size_t>(T) * N * 3);
      std::vector<double> world_turn(data.up ? Bs : 0);  // the prior's view: the data's axes
      int64_t pseudo_futures = 0;                        // in the whole batch
      for (int w : picked) pseudo_futures += std::min<int64_t>(M, data.multimodal[w].size());
      for (int b = 0; b < Bs; ++b) {
        const int w = picked[share.begin + b];
        const WindowAugmentation& a = drawn[share.begin + b];
        float* dst = truth.data_ptr<float>() + static_cast<size_t>(b) * T * N * 3;
        // In the body's frame (Gather turns): the window, and each pseudo window as it was
        // matched, before its future is retargeted onto this window's last pose; each varied as
        // the window's draw says.
        const double speed = a.speed == 1 ? 1.0 : data.SharedSpeed(w, M, a.speed);
        data.Gather(w, dst, speed);
        vary(a, T, dst);
        if (data.up) world_turn[b] = -data.turn[w];
        const auto& mm = data.multimodal[w];
        for (int m = 0; m < std::min<int>(M, mm.size()); ++m) {
          data.GatherPseudo(w, m, other.data(), speed);
          vary(a, T, other.data());
          RetargetFuture(
              other.data() + static_cast<size_t>(data.t_his) * N * 3,
              dst + static_cast<size_t>(data.t_his - 1) * N * 3, node_parents, data.t_pred, N,
              pseudo.data_ptr<float>() + (static_cast<size_t>(b) * M + m) * data.t_pred * N * 3);
          mask[b][m] = 1.0f;
        }
      }
      std::vector<torch::Tensor> z = NestedLatents(Bh, t.samples_per_part, model.generator.nz, gen);
      for (torch::Tensor& zp : z) {
        const int64_t rows = zp.size(0) / Bh;  // latents per history
        zp = zp.slice(0, share.begin * rows, share.end * rows);
      }
      // The history the network reads: with history_noise, each window's own noise (seeded by
      // its place in the step, so that no worker draws another's).
      torch::Tensor history = truth.slice(1, 0, data.t_his);
      if (augment.history_noise > 0) {
        history = history.clone();
        const size_t per = static_cast<size_t>(data.t_his) * N * 3;
        for (int b = 0; b < Bs; ++b) {
          std::mt19937_64 noise(noise_seed + static_cast<uint64_t>(share.begin + b));
          AddNoise(augment.history_noise, per, noise, history.data_ptr<float>() + b * per);
        }
      }
      LossBatch batch{net->ForwardNested(history, z, t.samples_per_part),
                      truth,
                      pseudo,
                      mask,
                      t.samples_per_part,
                      plan.nodes,
                      node_parents,
                      data.t_his};
      if (workers.distributed() && pseudo_futures > 0)
        batch.pseudo_norm = static_cast<double>(Bh) / (static_cast<double>(Bs) * pseudo_futures);
      if (data.up) {
        batch.world_turn = std::move(world_turn);
        std::tie(batch.ground_a, batch.ground_b) = GroundAxes(*data.up);
      }
      const int64_t offset = std::uniform_int_distribution<int>(0, t.prior_frame_step - 1)(rng);
      const LossTerms terms =
          ComputeLosses(batch, config.losses, hooks, offset, t.prior_frame_step);
      DataParallelStep(workers, adam, terms.total, net->parameters(), weight, t.grad_clip);
      if (sums.empty()) {
        sums.emplace_back("total", 0.0);
        for (const auto& [name, v] : terms.terms) sums.emplace_back(name, 0.0);
      }
      sums[0].second += terms.total.item<double>();
      for (size_t k = 0; k < terms.terms.size(); ++k)
        sums[k + 1].second += terms.terms[k].second.item<double>();
      if (cb.step) {
        std::vector<std::pair<std::string, double>> means = sums;
        for (auto& m : means) m.second /= (it + 1);
        cb.step(epoch, double(it + 1) / iterations, means);
      }
    }
    // The epoch's mean terms over every worker's share (each weighted by its share).
    std::vector<double> totals;
    for (const auto& s : sums) totals.push_back(s.second * weight);
    workers.SumValues(&totals);
    for (size_t k = 0; k < sums.size(); ++k) sums[k].second = totals[k] / iterations;
    // (Synchronised batch norm keeps them equal already; averaging equal values changes nothing.)
    workers.AverageBuffers(*net);
    const double seconds = SecondsSince(epoch_start);
    if (workers.writes()) {
      AppendEpochLog(out / "log.csv", "lr", epoch, lr, seconds, sums);
      // Bundle first, then the checkpoint that marks the epoch as done.
      SaveGeneratorBundle(out_dir, model, net);
      net->train();
      SaveCheckpoint(ckpt.string(), "generator.pt", *net, adam, epoch + 1);
    }
    summary.epochs_done = epoch + 1;
    if (cb.epoch) cb.epoch(epoch, sums, seconds);
  }
  summary.seconds = SecondsSince(start);
  summary.workers = workers.world_size();
  summary.reduce_seconds = workers.reduce_seconds();
  summary.sync_seconds = workers.sum_seconds();
  summary.sync_calls = workers.sum_calls();
  summary.steps = static_cast<int64_t>(summary.epochs_done - summary.first_epoch) * iterations;
  for (const torch::Tensor& p : net->parameters()) summary.gradient_mb += p.numel() * 4e-6;
  return summary;
}

}  // namespace motionfork
