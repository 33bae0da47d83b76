#include "denoise/dvae_model.h"

#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

#include "core/parallel_for.h"
#include "denoise/dvae_net.h"
#include "denoise/dvae_objective.h"
#include "denoise/dvae_windows.h"
#include "denoise/refiner_blend.h"
#include "torch_util/parameters.h"

namespace motionfork {

struct DvaeModel::Impl {
  // The decoder is frozen: optimisation mode fits only the encoder's output (dvae_model.h).
  Impl(DvaeManifest m, DvaeNet n)
      : manifest(std::move(m)),
        net(std::move(n)),
        norm(std::make_unique<DvaeTensors>(manifest)),
        skeleton(std::make_shared<const Skeleton>(Skeleton::Build(manifest.skeleton))) {
    for (torch::Tensor& p : net->DecoderParameters()) p.set_requires_grad(false);
  }

  DvaeManifest manifest;
  DvaeNet net{nullptr};
  std::unique_ptr<DvaeTensors> norm;
  std::shared_ptr<const Skeleton> skeleton;
  std::mutex mutex;  // optimisation mode changes the encoder's weights for a while
};

const DvaeManifest& DvaeModel::manifest() const { return impl_->manifest; }
const Skeleton& DvaeModel::skeleton() const { return *impl_->skeleton; }
int DvaeModel::window() const { return impl_->manifest.model.window; }
int DvaeModel::joints() const { return impl_->skeleton->num_joints(); }

int64_t DvaeModel::num_parameters() const { return CountParameters(*impl_->net); }

void DvaeModel::set_threads(int threads) {
  if (threads < 1)
    throw std::invalid_argument("DvaeModel: expected >= 1 thread, got " + std::to_string(threads));
  threads_ = threads;
}

DvaeModel DvaeModel::FromNet(DvaeManifest manifest, DvaeNet net) {
  DvaeModel model;
  model.impl_ = std::make_shared<Impl>(std::move(manifest), std::move(net));
  return model;
}

namespace {

constexpr int64_t kChunk = 256;  // windows per pass

// A network of its own with the same weights (optimisation mode changes a copy's encoder only).
DvaeNet CopyNet(const DvaeManifest& manifest, const DvaeNet& from) {
  DvaeNet net = BuildDvaeNet(manifest);
  torch::NoGradGuard no_grad;
  const auto src = from->named_parameters(), src_buffers = from->named_buffers();
  for (auto& p : net->named_parameters()) p.value().copy_(src[p.key()]);
  for (auto& b : net->named_buffers()) b.value().copy_(src_buffers[b.key()]);
  for (torch::Tensor& p : net->DecoderParameters()) p.set_requires_grad(false);
  net->eval();
  return net;
}

void CheckSequences(const std::vector<std::vector<float>>& sequences, int joints) {
  const size_t F = static_cast<size_t>(joints) * 3;
  for (size_t s = 0; s < sequences.size(); ++s) {
    const std::vector<float>& q = sequences[s];
    if (q.empty() || q.size() % F != 0) {
      throw std::invalid_argument("denoise: sequence " + std::to_string(s) + " has " +
                                  std::to_string(q.size()) + " values, expected frames x " +
                                  std::to_string(joints) + " joints x 3");
    }
    for (size_t k = 0; k < q.size(); ++k) {
      if (!std::isfinite(q[k])) {
        throw std::invalid_argument(
            "denoise: sequence " + std::to_string(s) + " frame " + std::to_string(k / F) +
            " joint " + std::to_string((k % F) / 3) + " is not finite (" + std::to_string(q[k]) +
            "); fill missing values first (motionfork impute)");
      }
    }
  }
}

// Refiner mode: every window of the refiner's length corrected by the refiner, blended.
std::vector<std::vector<float>> RefineSequences(const DvaeManifest& manifest, DvaeNet& net,
                                                const DvaeTensors& norm,
                                                const std::vector<std::vector<float>>& sequences,
                                                int threads, int* windows,
                                                const std::function<void(double)>& progress) {
  if (!net->refiner) {
    throw std::invalid_argument(
        "denoise: mode refiner needs a bundle with a refiner (motionfork dvae refine)");
  }
  const int J = DvaeValues(manifest) / 3, F = 3 * J;
  std::vector<int> frames;
  for (const auto& q : sequences) frames.push_back(static_cast<int>(q.size() / F));
  std::vector<WindowCut> cuts =
      CutWindows(frames, manifest.refiner.window, manifest.refiner.stride);
  std::vector<std::vector<float>> values(cuts.size());
  for (size_t w = 0; w < cuts.size(); ++w)
    values[w] = WindowValues(sequences[cuts[w].sequence].data(), J, &cuts[w]);
  std::map<int, std::vector<size_t>> groups;  // length -> windows
  for (size_t w = 0; w < cuts.size(); ++w) groups[cuts[w].length].push_back(w);
  std::vector<std::pair<const std::vector<size_t>*, size_t>> items;  // (group, first member)
  for (const auto& [length, members] : groups) {
    for (size_t c0 = 0; c0 < members.size(); c0 += kChunk) items.emplace_back(&members, c0);
  }
  std::mutex progress_lock;
  size_t done = 0;
  ParallelFor(static_cast<int>(items.size()), threads, [&](int item, int) {
    const auto& [members, c0] = items[static_cast<size_t>(item)];
    const size_t c1 = std::min(members->size(), c0 + static_cast<size_t>(kChunk));
    const int64_t L = cuts[(*members)[c0]].length, B = static_cast<int64_t>(c1 - c0);
    std::vector<float> batch;
    for (size_t k = c0; k < c1; ++k)
      batch.insert(batch.end(), values[(*members)[k]].begin(), values[(*members)[k]].end());
    torch::NoGradGuard no_grad;
    const torch::Tensor y = norm.Normalise(batch.data(), B, L);
    const std::vector<float> metres = norm.Denormalise(y + net->refiner(y));
    for (size_t k = c0; k < c1; ++k) {
      const size_t off = (k - c0) * static_cast<size_t>(L) * F;
      values[(*members)[k]].assign(metres.begin() + off,
                                   metres.begin() + off + static_cast<size_t>(L) * F);
    }
    std::lock_guard<std::mutex> guard(progress_lock);
    done += static_cast<size_t>(B);
    if (progress) progress(static_cast<double>(done) / cuts.size());
  });
  *windows = static_cast<int>(cuts.size());
  return BlendWindows(cuts, values, frames, J);
}

}  // namespace

std::vector<std::vector<float>> DvaeModel::Denoise(
    const std::vector<std::vector<float>>& sequences, const DenoiseOptions& options,
    DenoiseStats* stats, const std::function<void(double)>& progress) const {
  Impl& i = *impl_;
  std::lock_guard<std::mutex> lock(i.mutex);
  const auto start = std::chrono::steady_clock::now();
  const int J = joints(), F = 3 * J;
  CheckSequences(sequences, J);
  if (options.mode == DenoiseMode::kRefiner) {
    int windows = 0;
    const RefinerBlend& blend = i.manifest.refiner_blend;
    const bool blended = options.refiner_blend && !blend.weights.empty();
    std::vector<std::vector<float>> repaired;
    if (blended && blend.outliers.enabled()) {
      for (const auto& q : sequences) repaired.push_back(RepairOutliers(q, J, blend.outliers));
    }
    const std::vector<std::vector<float>>& input = repaired.empty() ? sequences : repaired;
    std::vector<std::vector<float>> out = RefineSequences(
        i.manifest, i.net, *i.norm, input, std::max(1, threads_), &windows, progress);
    if (blended) {
      for (size_t q = 0; q < out.size(); ++q) out[q] = BlendRefined(input[q], out[q], J, blend);
    }
    if (stats) {
      stats->windows = windows;
      stats->seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      stats->noise_std.clear();  // the refiner estimates no noise level
    }
    return out;
  }
  std::vector<int> frames;
  for (const auto& q : sequences) frames.push_back(static_cast<int>(q.size() / F));
  std::vector<WindowCut> cuts = CutWindows(frames, window(), options.stride);
  std::vector<std::vector<float>> values(cuts.size());
  for (size_t w = 0; w < cuts.size(); ++w)
    values[w] = WindowValues(sequences[cuts[w].sequence].data(), J, &cuts[w]);

  // Batches: windows of one length (and, in optimisation mode, of one sequence).
  const bool optimise = options.mode == DenoiseMode::kOptimisation && options.iterations > 0;
  std::map<std::pair<int, int>, std::vector<size_t>> groups;  // (sequence or -1, length) -> windows
  for (size_t w = 0; w < cuts.size(); ++w)
    groups[{optimise ? cuts[w].sequence : -1, cuts[w].length}].push_back(w);

  // Work items: chunks of the groups, each with its own generator (ItemSeed(seed, item)), shared
  // by the threads; optimisation mode changes the encoder, so each extra thread has its own copy.
  struct Item {
    const std::vector<size_t>* members;
    int64_t length;
    size_t c0, c1;
  };
  std::vector<Item> items;
  for (const auto& [key, members] : groups) {
    for (size_t c0 = 0; c0 < members.size(); c0 += kChunk)
      items.push_back(
          {&members, key.second, c0, std::min(members.size(), c0 + static_cast<size_t>(kChunk))});
  }
  const int threads = std::max(1, std::min<int>(threads_, static_cast<int>(items.size())));
  std::vector<DvaeNet> nets{i.net};
  for (int t = 1; t < threads; ++t) nets.push_back(optimise ? CopyNet(i.manifest, i.net) : i.net);
  std::vector<std::vector<double>> joint_vars(items.size());
  std::mutex progress_lock;
  size_t done = 0;
  ParallelFor(static_cast<int>(items.size()), threads, [&](int item, int worker) {
    const Item& it = items[static_cast<size_t>(item)];
    DvaeNet& net = nets[static_cast<size_t>(worker)];
    at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(ItemSeed(options.seed, item));
    const int64_t L = it.length;
    std::vector<float> batch;
    for (size_t k = it.c0; k < it.c1; ++k)
      batch.insert(batch.end(), values[(*it.members)[k]].begin(), values[(*it.members)[k]].end());
    const int64_t B = static_cast<int64_t>(it.c1 - it.c0);
    const torch::Tensor y = i.norm->Normalise(batch.data(), B, L);  // a new tensor, not a view
    std::vector<torch::Tensor> encoder, saved;
    if (optimise) {
      // Adam on this sequence's own unsupervised loss, from the bundle's weights; restored after.
      encoder = net->EncoderParameters();
      for (const torch::Tensor& p : encoder) saved.push_back(p.detach().clone());
      net->train();
      torch::optim::Adam adam(encoder, torch::optim::AdamOptions(options.learning_rate));
      for (int step = 0; step < options.iterations; ++step) {
        const DenoiseTerms t = DenoiseObjective(net, *i.norm, y, 1.0, options.bone_weight, gen);
        adam.zero_grad();
        t.loss.backward();
        adam.step();
      }
      net->eval();
    }
    torch::NoGradGuard no_grad;
    torch::Tensor var;
    const torch::Tensor out =
        DenoiseOutput(net, *i.norm, y, options.samples, options.fuse, gen, &var);
    for (size_t p = 0; p < saved.size(); ++p) encoder[p].copy_(saved[p]);
    const std::vector<float> metres = i.norm->Denormalise(out);
    for (size_t k = it.c0; k < it.c1; ++k) {
      const size_t off = (k - it.c0) * static_cast<size_t>(L) * F;
      values[(*it.members)[k]].assign(metres.begin() + off,
                                      metres.begin() + off + static_cast<size_t>(L) * F);
    }
    const torch::Tensor joint_var =
        (var * i.norm->std().pow(2)).reshape({B * L, J, 3}).sum(2).sum(0).to(torch::kFloat64);
    joint_vars[static_cast<size_t>(item)].assign(joint_var.data_ptr<double>(),
                                                 joint_var.data_ptr<double>() + J);
    std::lock_guard<std::mutex> guard(progress_lock);
    done += static_cast<size_t>(B);
    if (progress) progress(static_cast<double>(done) / cuts.size());
  });
  std::vector<double> noise_sum(J, 0.0);
  double noise_count = 0;
  for (size_t k = 0; k < items.size(); ++k) {  // in item order, whatever the threads
    for (int j = 0; j < J; ++j) noise_sum[j] += joint_vars[k][static_cast<size_t>(j)] / 3.0;
    noise_count += static_cast<double>((items[k].c1 - items[k].c0) * items[k].length);
  }
  std::vector<std::vector<float>> result = BlendWindows(cuts, values, frames, J);
  if (stats) {
    stats->windows = static_cast<int>(cuts.size());
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->noise_std.assign(J, 0.0);
    for (int j = 0; j < J; ++j)
      stats->noise_std[j] = std::sqrt(noise_sum[j] / std::max(1.0, noise_count));
  }
  return result;
}

Motion DenoiseMotion(const DvaeModel& model, const Motion& motion, const DenoiseOptions& options,
                     DenoiseStats* stats, const std::function<void(double)>& progress) {
  const Skeleton& want = model.skeleton();
  if (motion.skeleton().joint_names() != want.joint_names()) {
    throw std::invalid_argument("the motion's joints do not match the Motion-DVAE's skeleton '" +
                                want.name() + "' (" + std::to_string(want.num_joints()) +
                                " joints; pass --skeleton to map them)");
  }
  if (std::abs(motion.fps() - model.manifest().fps) > 1e-6) {
    throw std::invalid_argument("the motion is at " + std::to_string(motion.fps()) +
                                " Hz, the Motion-DVAE at " + std::to_string(model.manifest().fps) +
                                " Hz");
  }
  std::vector<std::vector<float>> out =
      model.Denoise({motion.positions()}, options, stats, progress);
  return Motion(motion.skeleton_ptr(), motion.fps(), std::move(out[0]));
}

}  // namespace motionfork
