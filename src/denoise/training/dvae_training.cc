#include "denoise/training/dvae_training.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include "bundle/dvae_bundle.h"
#include "core/motion_noise.h"
#include "dataset/windows.h"
#include "denoise/dvae_objective.h"
#include "denoise/dvae_windows.h"
#include "io/file_util.h"
#include "torch_util/checkpoint.h"
#include "torch_util/threads.h"

namespace motionfork {

namespace fs = std::filesystem;

DvaeData MakeDvaeData(const Dataset& dataset, double held_out_share, uint64_t seed, int window) {
  DvaeData data;
  std::vector<int> clips;
  for (int c : dataset.ClipIndices(Split::kTrain)) {
    if (dataset.clips[c].motion.num_frames() >= window) clips.push_back(c);
  }
  if (clips.size() < 2) {
    throw std::invalid_argument(
        "Motion-DVAE training: expected at least 2 training clips of >= " + std::to_string(window) +
        " frames, found " + std::to_string(clips.size()));
  }
  std::vector<int> order = clips;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(seed));
  const size_t held =
      std::max<size_t>(1, static_cast<size_t>(std::lround(held_out_share * order.size())));
  const std::set<int> held_out(order.begin(), order.begin() + held);
  for (int c : clips) {
    (held_out.count(c) ? data.held_out : data.train).push_back(dataset.clips[c].motion.positions());
  }
  data.joints = dataset.clips[clips[0]].motion.num_joints();
  return data;
}

namespace {

// Window values of many windows of one length, [count, length, J * 3].
struct WindowBatch {
  std::vector<float> values;
  int64_t count = 0;
};

void AddWindow(const std::vector<float>& clip, int joints, int start, int length, WindowBatch* b) {
  WindowCut cut{0, start, length, {}};
  const std::vector<float> v = WindowValues(clip.data(), joints, &cut);
  b->values.insert(b->values.end(), v.begin(), v.end());
  ++b->count;
}

// Held-out windows: every clip cut every `window` frames, at most `limit`, in order.
WindowBatch HeldOutBatch(const DvaeData& data, int window, int limit) {
  WindowBatch b;
  const int F = 3 * data.joints;
  for (const auto& clip : data.held_out) {
    const int frames = static_cast<int>(clip.size() / F);
    for (int s = 0; s + window <= frames && b.count < limit; s += window)
      AddWindow(clip, data.joints, s, window, &b);
  }
  return b;
}

std::vector<int> ClipFrames(const std::vector<std::vector<float>>& clips, int values) {
  std::vector<int> frames;
  for (const auto& c : clips) frames.push_back(static_cast<int>(c.size() / values));
  return frames;
}

void ComputeNormalisation(const DvaeData& data, int window, DvaeManifest* m) {
  const int F = 3 * data.joints;
  std::vector<double> sum(F, 0.0), sq(F, 0.0);
  double count = 0;
  for (const auto& clip : data.train) {
    const int frames = static_cast<int>(clip.size() / F);
    for (int s = 0; s + window <= frames; s += window) {
      WindowCut cut{0, s, window, {}};
      const std::vector<float> v = WindowValues(clip.data(), data.joints, &cut);
      for (size_t i = 0; i < v.size(); ++i) {
        sum[i % F] += v[i];
        sq[i % F] += double(v[i]) * v[i];
      }
      count += window;
    }
  }
  m->mean.assign(F, 0.0);
  m->std.assign(F, 1.0);
  for (int f = 0; f < F; ++f) {
    m->mean[f] = sum[f] / count;
    m->std[f] = std::max(1e-3, std::sqrt(std::max(0.0, sq[f] / count - m->mean[f] * m->mean[f])));
  }
}

double AnnealWeight(int epochs, double start, double progress) {
  if (epochs <= 0) return 1.0;
  return start + (1.0 - start) * std::min(1.0, progress / epochs);
}

void SetLearningRate(torch::optim::Adam& adam, double lr) {
  for (auto& group : adam.param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
}

// Appends one epoch to OUT/log.csv (header first when the file is new).
void AppendLog(const fs::path& file, const DvaeEpochLog& log) {
  const bool fresh = !fs::exists(file);
  std::ofstream csv(file, std::ios::app);
  if (fresh) {
    csv << "epoch,kl_weight,seconds";
    for (const auto& kv : log.terms) csv << "," << kv.first;
    csv << "\n";
  }
  csv << log.epoch + 1 << "," << log.kl_weight << "," << log.seconds;
  for (const auto& kv : log.terms) csv << "," << kv.second;
  csv << "\n";
}

void SetInfo(DvaeManifest* m, const std::string& key, const std::string& value) {
  m->info.erase(std::remove_if(m->info.begin(), m->info.end(),
                               [&](const auto& kv) { return kv.first == key; }),
                m->info.end());
  m->info.emplace_back(key, value);
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

DvaeTrainSummary TrainDvae(const DvaeTrainConfig& config, const DvaeManifest& base,
                           const DvaeData& data, const std::string& out_dir,
                           const DvaeTrainCallbacks& cb, int stop_after_epochs) {
  const DvaeTrainOptions& t = config.training;
  PinThreads(t.threads);
  torch::manual_seed(t.seed);
  DvaeManifest m = base;
  m.model = config.model;
  const int W = m.model.window, J = data.joints, F = 3 * J;
  ComputeNormalisation(data, W, &m);
  const DvaeTensors norm(m);
  DvaeNet net = BuildDvaeNet(m);
  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(t.learning_rate));
  const fs::path out(out_dir), ckpt = out / "checkpoint";
  fs::create_directories(ckpt);
  DvaeTrainSummary summary;
  summary.first_epoch = LoadCheckpoint(ckpt.string(), "dvae.pt", *net, adam);
  if (summary.first_epoch > 0 && cb.message) {
    cb.message("resuming from " + ckpt.string() + " after epoch " +
               std::to_string(summary.first_epoch));
  }
  const std::vector<int> frames = ClipFrames(data.train, F);
  const WindowBatch held = HeldOutBatch(data, W, t.held_out_windows);
  const int iterations = t.windows_per_epoch / t.batch_size, B = t.batch_size;
  const auto start = std::chrono::steady_clock::now();
  for (int epoch = summary.first_epoch; epoch < t.epochs; ++epoch) {
    if (stop_after_epochs > 0 && epoch - summary.first_epoch >= stop_after_epochs) break;
    const auto epoch_start = std::chrono::steady_clock::now();
    SetLearningRate(adam, t.learning_rate * std::pow(t.lr_decay, epoch));
    net->train();
    RandomWindowSampler sampler(frames, W, t.seed * 1000003ull + epoch);
    at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(t.seed * 104729ull + epoch);
    double sums[5] = {0, 0, 0, 0, 0}, beta = 0;
    for (int it = 0; it < iterations; ++it) {
      WindowBatch batch;
      for (int b = 0; b < B; ++b) {
        const Window w = sampler.Next();
        AddWindow(data.train[w.clip], J, w.start, W, &batch);
      }
      const torch::Tensor x = norm.Normalise(batch.values.data(), B, W);
      beta = AnnealWeight(t.kl_anneal_epochs, t.kl_start,
                          epoch + static_cast<double>(it) / iterations);
      const PriorTerms terms = PriorObjective(net, norm, x, beta, t.bone_weight, gen);
      adam.zero_grad();
      terms.loss.backward();
      torch::nn::utils::clip_grad_norm_(net->parameters(), t.grad_clip);
      adam.step();
      const double v[5] = {terms.loss.item<double>(), terms.nll.item<double>(),
                           terms.kl.item<double>(), terms.bone.item<double>(),
                           terms.x0.item<double>()};
      if (!std::isfinite(v[0])) {
        throw std::runtime_error("Motion-DVAE training: the loss became non-finite at epoch " +
                                 std::to_string(epoch + 1));
      }
      for (int k = 0; k < 5; ++k) sums[k] += v[k];
      if (cb.step) cb.step(epoch, double(it + 1) / iterations, sums[0] / (it + 1));
    }
    // Held-out: negative ELBO (one posterior sample, fixed seed) and the reconstruction error of
    // the posterior means, cm per joint.
    net->eval();
    double nelbo = 0, mpjpe = 0;
    {
      torch::NoGradGuard no_grad;
      at::Generator eval_gen = at::make_generator<at::CPUGeneratorImpl>(t.seed + 17);
      const torch::Tensor x = norm.Normalise(held.values.data(), held.count, W);
      const PriorTerms ht = PriorObjective(net, norm, x, 1.0, 0.0, eval_gen);
      nelbo = (ht.nll + ht.kl).item<double>();
      const DvaePass p = net->Run(x, x.select(1, 0), false, c10::nullopt);
      const torch::Tensor d =
          ((p.mean - x.slice(1, 1)) * norm.std()).reshape({held.count, W - 1, J, 3});
      mpjpe = d.norm(2, -1).mean().item<double>() * 100;
    }
    DvaeEpochLog log;
    log.epoch = epoch;
    log.kl_weight = beta;
    log.seconds = Seconds(epoch_start);
    log.terms = {{"loss", sums[0] / iterations},   {"nll", sums[1] / iterations},
                 {"kl", sums[2] / iterations},     {"bone_cm2", sums[3] / iterations},
                 {"x0_nll", sums[4] / iterations}, {"held_out_neg_elbo", nelbo},
                 {"held_out_recon_cm", mpjpe}};
    AppendLog(out / "log.csv", log);
    SetInfo(&m, "epochs_trained", std::to_string(epoch + 1));
    SaveDvaeBundle(out_dir, m, net);
    SaveCheckpoint(ckpt.string(), "dvae.pt", *net, adam, epoch + 1);
    summary.epochs_done = epoch + 1;
    if (cb.epoch) cb.epoch(log);
  }
  summary.seconds = Seconds(start);
  return summary;
}

DvaeTrainSummary FinetuneDvae(const DvaeTrainConfig& config, const std::string& prior_dir,
                              const DvaeData& data, const std::string& out_dir,
                              const DvaeTrainCallbacks& cb, int stop_after_epochs) {
  const DvaeFinetuneOptions& t = config.finetune;
  PinThreads(t.threads);
  torch::manual_seed(t.seed);
  DvaeManifest m;
  DvaeNet net = LoadDvaeBundle(prior_dir, &m);
  if (m.finetuned) {
    throw std::invalid_argument(
        prior_dir +
        ": this bundle is fine-tuned already; fine-tune the motion prior (dvae train's output)");
  }
  const int W = m.model.window, J = data.joints, F = 3 * J;
  if (DvaeValues(m) != F)
    throw std::invalid_argument(prior_dir + ": the bundle's skeleton does not match the data's");
  m.finetuned = true;
  m.finetune_noise = t.noise;
  m.noise_prior = config.noise_prior;
  m.denoise = config.denoise;
  SetInfo(&m, "finetune_config", config.name);
  const DvaeTensors norm(m);
  for (torch::Tensor& p : net->DecoderParameters()) p.set_requires_grad(false);
  const std::vector<torch::Tensor> trained = net->EncoderParameters();
  torch::optim::Adam adam(trained, torch::optim::AdamOptions(t.learning_rate));
  std::vector<NoiseSpec> kinds;
  for (const std::string& s : t.noise) kinds.push_back(ParseNoiseSpec(s));

  const fs::path out(out_dir), ckpt = out / "checkpoint", state = ckpt / "finetune_best.txt";
  fs::create_directories(ckpt);
  DvaeTrainSummary summary;
  summary.first_epoch = LoadCheckpoint(ckpt.string(), "dvae.pt", *net, adam);
  double best = INFINITY;
  int bad_epochs = 0;
  if (summary.first_epoch > 0) {
    std::ifstream in(state);
    in >> best >> bad_epochs;
    if (cb.message)
      cb.message("resuming from " + ckpt.string() + " after epoch " +
                 std::to_string(summary.first_epoch));
  }
  // Held-out noisy windows, the same every epoch: each window gets every noise kind in turn.
  const WindowBatch clean = HeldOutBatch(data, W, 1000);
  WindowBatch noisy = clean;
  {
    std::mt19937_64 rng(t.seed + 99);
    for (int64_t w = 0; w < noisy.count; ++w) {
      AddNoise(kinds[w % kinds.size()], noisy.values.data() + w * W * F, W, J, rng);
    }
  }
  const std::vector<int> frames = ClipFrames(data.train, F);
  const int iterations = t.windows_per_epoch / t.batch_size, B = t.batch_size;
  const auto start = std::chrono::steady_clock::now();
  for (int epoch = summary.first_epoch; epoch < t.epochs; ++epoch) {
    if (stop_after_epochs > 0 && epoch - summary.first_epoch >= stop_after_epochs) break;
    if (bad_epochs >= t.patience) {
      summary.stopped_early = true;
      break;
    }
    const auto epoch_start = std::chrono::steady_clock::now();
    net->train();
    RandomWindowSampler sampler(frames, W, t.seed * 1000003ull + epoch);
    std::mt19937_64 rng(t.seed * 7919ull + epoch);
    at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(t.seed * 104729ull + epoch);
    double sums[5] = {0, 0, 0, 0, 0}, beta = 0;
    std::vector<float> noisy_clip;
    for (int it = 0; it < iterations; ++it) {
      WindowBatch batch;
      for (int b = 0; b < B; ++b) {
        const Window w = sampler.Next();
        const std::vector<float>& clip = data.train[w.clip];
        noisy_clip.assign(clip.begin() + static_cast<size_t>(w.start) * F,
                          clip.begin() + static_cast<size_t>(w.start + W) * F);
        AddNoise(kinds[rng() % kinds.size()], noisy_clip.data(), W, J, rng);
        AddWindow(noisy_clip, J, 0, W, &batch);
      }
      const torch::Tensor y = norm.Normalise(batch.values.data(), B, W);
      beta = AnnealWeight(t.kl_anneal_epochs, t.kl_start,
                          epoch + static_cast<double>(it) / iterations);
      const DenoiseTerms terms = DenoiseObjective(net, norm, y, beta, t.bone_weight, gen);
      adam.zero_grad();
      terms.loss.backward();
      torch::nn::utils::clip_grad_norm_(trained, t.grad_clip);
      adam.step();
      const double v[5] = {terms.loss.item<double>(), terms.data.item<double>(),
                           terms.kl_z.item<double>(), terms.kl_v.item<double>(),
                           terms.bone.item<double>()};
      if (!std::isfinite(v[0])) {
        throw std::runtime_error("Motion-DVAE fine-tuning: the loss became non-finite at epoch " +
                                 std::to_string(epoch + 1));
      }
      for (int k = 0; k < 5; ++k) sums[k] += v[k];
      if (cb.step) cb.step(epoch, double(it + 1) / iterations, sums[0] / (it + 1));
    }
    net->eval();
    double held_loss = 0, err_noisy = 0, err_denoised = 0;
    {
      torch::NoGradGuard no_grad;
      at::Generator eval_gen = at::make_generator<at::CPUGeneratorImpl>(t.seed + 17);
      const torch::Tensor y = norm.Normalise(noisy.values.data(), noisy.count, W);
      const torch::Tensor x = norm.Normalise(clean.values.data(), clean.count, W);
      held_loss = DenoiseObjective(net, norm, y, 1.0, t.bone_weight, eval_gen).loss.item<double>();
      const torch::Tensor out = DenoiseOutput(net, norm, y, 0, true, eval_gen);
      auto cm = [&](const torch::Tensor& a) {
        return ((a - x) * norm.std())
                   .reshape({noisy.count, W, J, 3})
                   .norm(2, -1)
                   .mean()
                   .item<double>() *
               100;
      };
      err_noisy = cm(y);
      err_denoised = cm(out);
    }
    DvaeEpochLog log;
    log.epoch = epoch;
    log.kl_weight = beta;
    log.seconds = Seconds(epoch_start);
    log.terms = {{"loss", sums[0] / iterations},     {"data", sums[1] / iterations},
                 {"kl_z", sums[2] / iterations},     {"kl_v", sums[3] / iterations},
                 {"bone_cm2", sums[4] / iterations}, {"held_out_loss", held_loss},
                 {"held_out_noisy_cm", err_noisy},   {"held_out_denoised_cm", err_denoised}};
    AppendLog(out / "log.csv", log);
    if (held_loss < best) {
      best = held_loss;
      bad_epochs = 0;
      SetInfo(&m, "finetune_epoch", std::to_string(epoch + 1));
      SaveDvaeBundle(out_dir, m, net);
    } else {
      ++bad_epochs;
    }
    std::ostringstream st;
    st.precision(17);
    st << best << " " << bad_epochs << "\n";
    WriteFileAtomically(state.string(), st.str());
    SaveCheckpoint(ckpt.string(), "dvae.pt", *net, adam, epoch + 1);
    summary.epochs_done = epoch + 1;
    if (cb.epoch) cb.epoch(log);
  }
  summary.seconds = Seconds(start);
  return summary;
}

}  // namespace motionfork
