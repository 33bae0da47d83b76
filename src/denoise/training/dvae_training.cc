#include "denoise/training/dvae_training.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <random>
#include <set>
#include <sstream>

#include "bundle/dvae_bundle.h"
#include "bundle/manifest.h"
#include "core/motion_noise.h"
#include "core/resample.h"
#include "dataset/windows.h"
#include "denoise/denoise_metrics.h"
#include "denoise/dvae_objective.h"
#include "denoise/dvae_windows.h"
#include "denoise/refiner_blend.h"
#include "launch/worker_place.h"
#include "torch_util/checkpoint.h"
#include "torch_util/data_parallel.h"
#include "torch_util/parameters.h"
#include "torch_util/threads.h"
#include "torch_util/training_loop.h"

namespace motionfork {

namespace fs = std::filesystem;

DvaeData MakeDvaeData(const Dataset& dataset, double held_out_share, uint64_t seed, int window) {
  DvaeData data;
  const HeldOutClips split =
      HoldOutTrainingClips(dataset, window, held_out_share, seed, "Motion-DVAE training");
  for (int c : split.clips) {
    (split.held_out.count(c) ? data.held_out : data.train)
        .push_back(dataset.clips[c].motion.positions());
  }
  data.joints = dataset.clips[split.clips[0]].motion.num_joints();
  return data;
}

long long DvaeData::train_frames() const {
  long long frames = 0;
  for (const auto& clip : train) frames += clip.size() / (3 * joints);
  return frames;
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

// Step `it` of `iterations`: its N loss terms (the loss first, which must be finite: `what`
// names the run in the error) added to the epoch's sums, the mean loss so far to cb.step.
template <size_t N>
void AddStep(const std::array<torch::Tensor, N>& terms, const char* what, int epoch, int it,
             int iterations, const DvaeTrainCallbacks& cb, double (&sums)[N]) {
  double v[N];
  for (size_t k = 0; k < N; ++k) v[k] = terms[k].template item<double>();
  RequireFiniteLoss(v[0], what, epoch);
  for (size_t k = 0; k < N; ++k) sums[k] += v[k];
  if (cb.step) cb.step(epoch, double(it + 1) / iterations, sums[0] / (it + 1));
}

// The epoch's sums over every worker's share (each weighted by its share of the batch).
template <size_t N>
void SumOverWorkers(DataParallel& workers, double weight, double (&sums)[N]) {
  std::vector<double> totals(sums, sums + N);
  for (double& v : totals) v *= weight;
  workers.SumValues(&totals);
  std::copy(totals.begin(), totals.end(), sums);
}

// An epoch's log, appended to `file` (OUT/log.csv) when `write`: the means over the epoch's
// `iterations` steps of their N terms (`names`), then the held-out figures.
template <size_t N>
DvaeEpochLog LogEpoch(const fs::path& file, bool write, int epoch, double kl_weight, double seconds,
                      const std::array<const char*, N>& names, const double (&sums)[N],
                      int iterations,
                      std::initializer_list<std::pair<std::string, double>> held_out) {
  DvaeEpochLog log;
  log.epoch = epoch;
  log.kl_weight = kl_weight;
  log.seconds = seconds;
  for (size_t k = 0; k < N; ++k) log.terms.emplace_back(names[k], sums[k] / iterations);
  log.terms.insert(log.terms.end(), held_out.begin(), held_out.end());
  if (write) AppendEpochLog(file, "kl_weight", log.epoch, log.kl_weight, log.seconds, log.terms);
  return log;
}

std::vector<NoiseSpec> ParseNoiseSpecs(const std::vector<std::string>& texts) {
  std::vector<NoiseSpec> kinds;
  for (const std::string& s : texts) kinds.push_back(ParseNoiseSpec(s));
  return kinds;
}

// The early-stopping run of fine-tuning and refiner training: its checkpoint keeps, besides the
// weights and Adam, the best held-out figure so far and the epochs since it improved.
class BestEpochRun {
 public:
  BestEpochRun(const fs::path& out, const char* state_name, const char* info_key)
      : out_(out), ckpt_(out / "checkpoint"), state_(ckpt_ / state_name), info_key_(info_key) {}

  // Rank 0 resumes; every worker takes its state. Returns the epochs done.
  int Resume(DataParallel& workers, DvaeNet& net, torch::optim::Adam& adam,
             const DvaeTrainCallbacks& cb) {
    std::vector<double> resumed = {0, INFINITY, 0};  // epochs done, best, bad epochs
    if (workers.writes()) {
      resumed[0] = ResumeTraining(ckpt_, "dvae.pt", *net, adam, out_ / "log.csv", cb.message);
      if (resumed[0] > 0) {
        std::ifstream in(state_);
        in >> resumed[1] >> resumed[2];
      }
    }
    workers.BroadcastTrainingState(*net, adam, &resumed);
    best_ = resumed[1];
    bad_epochs_ = static_cast<int>(resumed[2]);
    return static_cast<int>(resumed[0]);
  }

  bool Stalled(int patience) const { return bad_epochs_ >= patience; }

  // After epoch `epoch`: the bundle when `figure` (lower is better) improved, then the checkpoint.
  void EndEpoch(DataParallel& workers, int epoch, double figure, DvaeManifest* m, DvaeNet& net,
                torch::optim::Adam& adam) {
    if (figure < best_) {
      best_ = figure;
      bad_epochs_ = 0;
      SetManifestInfo(&m->info, info_key_, std::to_string(epoch + 1));
      if (workers.writes()) SaveDvaeBundle(out_.string(), *m, net);
    } else {
      ++bad_epochs_;
    }
    std::ostringstream st;
    st.precision(17);
    st << best_ << " " << bad_epochs_ << "\n";
    if (workers.writes()) {
      SaveCheckpoint(ckpt_.string(), "dvae.pt", *net, adam, epoch + 1,
                     {{state_.filename().string(), st.str()}});
    }
  }

 private:
  fs::path out_, ckpt_, state_;
  const char* info_key_;
  double best_ = INFINITY;
  int bad_epochs_ = 0;
};

}  // namespace

DvaeTrainSummary TrainDvae(const DvaeTrainConfig& config, const DvaeManifest& base,
                           const DvaeData& data, const std::string& out_dir,
                           const DvaeTrainCallbacks& cb, int stop_after_epochs) {
  const DvaeTrainOptions& t = config.training;
  DataParallel& workers = TrainingWorkers();
  PinThreads(workers.ThreadsPerWorker(t.threads));
  torch::manual_seed(t.seed);
  DvaeManifest m = base;
  m.model = config.model;
  const int W = m.model.window, J = data.joints, F = 3 * J;
  ComputeNormalisation(data, W, &m);
  const DvaeTensors norm(m);
  DvaeNet net = BuildDvaeNet(m);
  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(t.learning_rate));
  const fs::path out(out_dir), ckpt = out / "checkpoint";
  DvaeTrainSummary summary;
  std::vector<double> resumed = {0};
  if (workers.writes())
    resumed[0] = ResumeTraining(ckpt, "dvae.pt", *net, adam, out / "log.csv", cb.message);
  workers.BroadcastTrainingState(*net, adam, &resumed);
  summary.first_epoch = static_cast<int>(resumed[0]);
  const std::vector<int> frames = ClipFrames(data.train, F);
  const WindowBatch held = HeldOutBatch(data, W, t.held_out_windows);
  const int iterations = t.windows_per_epoch / t.batch_size, B = t.batch_size;
  workers.RequireBatch(B, "training.batch_size");
  const Share share = workers.BatchShare(B);  // this worker's windows of every step
  const int Bs = static_cast<int>(share.size());
  const double weight = static_cast<double>(Bs) / B;
  const auto start = std::chrono::steady_clock::now();
  for (int epoch = summary.first_epoch; epoch < t.epochs; ++epoch) {
    if (stop_after_epochs > 0 && epoch - summary.first_epoch >= stop_after_epochs) break;
    const auto epoch_start = std::chrono::steady_clock::now();
    SetLearningRate(adam, t.learning_rate * std::pow(t.lr_decay, epoch));
    net->train();
    RandomWindowSampler sampler(frames, W, t.seed * 1000003ull + epoch);
    at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(t.seed * 104729ull + epoch +
                                                                 1000000007ull * workers.rank());
    double sums[5] = {0, 0, 0, 0, 0}, beta = 0;
    for (int it = 0; it < iterations; ++it) {
      WindowBatch batch;
      for (int b = 0; b < B; ++b) {
        const Window w = sampler.Next();
        if (b >= share.begin && b < share.end) AddWindow(data.train[w.clip], J, w.start, W, &batch);
      }
      const torch::Tensor x = norm.Normalise(batch.values.data(), Bs, W);
      beta = AnnealedWeight(t.kl_start, t.kl_anneal_epochs,
                            epoch + static_cast<double>(it) / iterations);
      const PriorTerms terms = PriorObjective(net, norm, x, beta, t.bone_weight, gen);
      DataParallelStep(workers, adam, terms.loss, net->parameters(), weight, t.grad_clip);
      AddStep({terms.loss, terms.nll, terms.kl, terms.bone, terms.x0}, "Motion-DVAE training",
              epoch, it, iterations, cb, sums);
    }
    SumOverWorkers(workers, weight, sums);
    workers.AverageBuffers(*net);
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
    const DvaeEpochLog log =
        LogEpoch(out / "log.csv", workers.writes(), epoch, beta, SecondsSince(epoch_start),
                 {"loss", "nll", "kl", "bone_cm2", "x0_nll"}, sums, iterations,
                 {{"held_out_neg_elbo", nelbo}, {"held_out_recon_cm", mpjpe}});
    SetManifestInfo(&m.info, "epochs_trained", std::to_string(epoch + 1));
    if (workers.writes()) {
      SaveDvaeBundle(out_dir, m, net);
      SaveCheckpoint(ckpt.string(), "dvae.pt", *net, adam, epoch + 1);
    }
    summary.epochs_done = epoch + 1;
    if (cb.epoch) cb.epoch(log);
  }
  summary.seconds = SecondsSince(start);
  return summary;
}

DvaeTrainSummary FinetuneDvae(const DvaeTrainConfig& config, const std::string& prior_dir,
                              const DvaeData& data, const std::string& out_dir,
                              const DvaeTrainCallbacks& cb, int stop_after_epochs) {
  const DvaeFinetuneOptions& t = config.finetune;
  DataParallel& workers = TrainingWorkers();
  PinThreads(workers.ThreadsPerWorker(t.threads));
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
  if (m.denoise.mode == DenoiseMode::kRefiner)
    m.denoise.mode = DenoiseMode::kRegression;  // none yet
  SetManifestInfo(&m.info, "finetune_config", config.name);
  const DvaeTensors norm(m);
  for (torch::Tensor& p : net->DecoderParameters()) p.set_requires_grad(false);
  const std::vector<torch::Tensor> trained = net->EncoderParameters();
  torch::optim::Adam adam(trained, torch::optim::AdamOptions(t.learning_rate));
  const std::vector<NoiseSpec> kinds = ParseNoiseSpecs(t.noise);

  const fs::path out(out_dir);
  BestEpochRun run(out, "finetune_best.txt", "finetune_epoch");
  DvaeTrainSummary summary;
  summary.first_epoch = run.Resume(workers, net, adam, cb);
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
  workers.RequireBatch(B, "finetune.batch_size");
  const Share share = workers.BatchShare(B);  // this worker's windows of every step
  const int Bs = static_cast<int>(share.size());
  const double weight = static_cast<double>(Bs) / B;
  const auto start = std::chrono::steady_clock::now();
  for (int epoch = summary.first_epoch; epoch < t.epochs; ++epoch) {
    if (stop_after_epochs > 0 && epoch - summary.first_epoch >= stop_after_epochs) break;
    if (run.Stalled(t.patience)) {
      summary.stopped_early = true;
      break;
    }
    const auto epoch_start = std::chrono::steady_clock::now();
    net->train();
    RandomWindowSampler sampler(frames, W, t.seed * 1000003ull + epoch);
    std::mt19937_64 rng(t.seed * 7919ull + epoch);
    at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(t.seed * 104729ull + epoch +
                                                                 1000000007ull * workers.rank());
    double sums[5] = {0, 0, 0, 0, 0}, beta = 0;
    std::vector<float> noisy_clip;
    for (int it = 0; it < iterations; ++it) {
      WindowBatch batch;
      for (int b = 0; b < B; ++b) {  // every window's noise drawn, this worker's share kept
        const Window w = sampler.Next();
        const std::vector<float>& clip = data.train[w.clip];
        noisy_clip.assign(clip.begin() + static_cast<size_t>(w.start) * F,
                          clip.begin() + static_cast<size_t>(w.start + W) * F);
        AddNoise(kinds[rng() % kinds.size()], noisy_clip.data(), W, J, rng);
        if (b >= share.begin && b < share.end) AddWindow(noisy_clip, J, 0, W, &batch);
      }
      const torch::Tensor y = norm.Normalise(batch.values.data(), Bs, W);
      beta = AnnealedWeight(t.kl_start, t.kl_anneal_epochs,
                            epoch + static_cast<double>(it) / iterations);
      const DenoiseTerms terms = DenoiseObjective(net, norm, y, beta, t.bone_weight, gen);
      DataParallelStep(workers, adam, terms.loss, trained, weight, t.grad_clip);
      AddStep({terms.loss, terms.data, terms.kl_z, terms.kl_v, terms.bone},
              "Motion-DVAE fine-tuning", epoch, it, iterations, cb, sums);
    }
    SumOverWorkers(workers, weight, sums);
    workers.AverageBuffers(*net);
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
    const DvaeEpochLog log =
        LogEpoch(out / "log.csv", workers.writes(), epoch, beta, SecondsSince(epoch_start),
                 {"loss", "data", "kl_z", "kl_v", "bone_cm2"}, sums, iterations,
                 {{"held_out_loss", held_loss},
                  {"held_out_noisy_cm", err_noisy},
                  {"held_out_denoised_cm", err_denoised}});
    run.EndEpoch(workers, epoch, held_loss, &m, net, adam);
    summary.epochs_done = epoch + 1;
    if (cb.epoch) cb.epoch(log);
  }
  summary.seconds = SecondsSince(start);
  return summary;
}

namespace {

// A clean window and its corrupted copy in the corrupted window's frame (both minus the corrupted
// window's mean root position, as the refiner sees them in use).
void AddWindowPair(const float* clean, const std::vector<float>& noisy, int joints, int length,
                   WindowBatch* input, WindowBatch* target) {
  WindowCut cut{0, 0, length, {}};
  const std::vector<float> v = WindowValues(noisy.data(), joints, &cut);
  input->values.insert(input->values.end(), v.begin(), v.end());
  ++input->count;
  const size_t n = static_cast<size_t>(length) * joints * 3;
  for (size_t k = 0; k < n; ++k) target->values.push_back(clean[k] - cut.root_mean[k % 3]);
  ++target->count;
}

using Motions = std::vector<std::vector<float>>;

// Each kind's motions blended by `blend` (into *blended when given), and the sum over the kinds
// of the log of their mean squared error against the clean motions ((0.1 mm)^2 added: a clean
// clip's floor), so that each kind counts by its relative error.
double BlendKinds(const std::vector<Motions>& inputs, const std::vector<Motions>& refined,
                  const Motions& clean, int joints, const RefinerBlend& blend,
                  std::vector<Motions>* blended = nullptr) {
  double log_error = 0;
  if (blended) blended->assign(inputs.size(), {});
  for (size_t k = 0; k < inputs.size(); ++k) {
    double squared = 0, values = 0;
    for (size_t q = 0; q < inputs[k].size(); ++q) {
      std::vector<float> b = BlendRefined(inputs[k][q], refined[k][q], joints, blend);
      for (size_t i = 0; i < b.size(); ++i) {
        const double e = b[i] - clean[q][i];
        squared += e * e;
      }
      values += static_cast<double>(b.size());
      if (blended) (*blended)[k].push_back(std::move(b));
    }
    log_error += std::log(squared / values + 1e-8);
  }
  return log_error;
}

// The denoised motion's acceleration over the clean motion's should lie within [1/x, x] (issue 25).
constexpr double kAccelRatioRange = 2.0;

// One of the specs at a uniform share of its level (sigma, and the rate of outliers).
NoiseSpec RandomLevel(const std::vector<NoiseSpec>& kinds, std::mt19937_64& rng) {
  NoiseSpec spec = kinds[rng() % kinds.size()];
  std::uniform_real_distribution<double> share(0.0, 1.0);
  spec.sigma *= share(rng);
  if (spec.kind == NoiseSpec::Kind::kOutliers) spec.rate *= share(rng);
  return spec;
}

// Mean distance per joint, cm, between normalised windows a and b [B, T, F].
torch::Tensor JointErrorCm(const torch::Tensor& a, const torch::Tensor& b, const DvaeTensors& norm,
                           int joints) {
  const torch::Tensor d = ((a - b) * norm.std()).reshape({a.size(0), a.size(1), joints, 3});
  return (d.pow(2).sum(-1) + 1e-12).sqrt().mean() * 100;
}

// The refiner's loss: joint error plus `accel_weight` x the joint error of the second differences.
torch::Tensor RefinerLoss(const torch::Tensor& refined, const torch::Tensor& clean,
                          const DvaeTensors& norm, int joints, double accel_weight) {
  torch::Tensor loss = JointErrorCm(refined, clean, norm, joints);
  if (accel_weight > 0) {
    auto accel = [](const torch::Tensor& x) {
      return x.slice(1, 2) - 2 * x.slice(1, 1, -1) + x.slice(1, 0, -2);
    };
    loss = loss + accel_weight * JointErrorCm(accel(refined), accel(clean), norm, joints);
  }
  return loss;
}

// The refiner's blend (refiner_blend.h) on whole held-out clips, as recorded and played twice as
// slow (a slower style), each clean and under the evaluation's noise kinds (other draws than any
// test) and small ones. For each outlier repair of the grid (outlier_repair.h; none among them) the
// inputs are repaired and refined, and for each roughness measure the weights fitted for each base
// smoothing, the one of least summed error kept; the repair and measure kept are the ones of least
// summed log error over the kinds (each kind counted by its relative error, so that outliers of 1
// cm weigh as much as noise of 10 cm). Then the output smoothing (fixed, or chosen per motion by
// its acceleration), with the measure as fitted or its median over the joints, of least summed log
// error among those whose noisy outputs move within 1/2x-2x the clean clips' acceleration at both
// speeds. (Fitting on 0.5 s histories cut from the clips as well lowered the weights of every bin
// and cost whole clips up to 0.26 cm on validation styles while leaving the forecast from a
// denoised clean history where it was: not done.)
RefinerBlend FitRefinerBlend(const DvaeModel& model, const DvaeData& data, uint64_t seed) {
  const std::vector<std::string> kinds = {"",
                                          "gaussian:0.01",
                                          "gaussian:0.02",
                                          "gaussian:0.05",
                                          "gaussian:0.10",
                                          "jitter:0.02",
                                          "outliers:0.1,0.3",
                                          "outliers:0.05,0.5",
                                          "jitter:0.05",
                                          "outliers:0.1,0.02",
                                          "outliers:0.1,0.05",
                                          "outliers:0.1,0.1",
                                          "outliers:0.1,0.01",
                                          "jitter:0.01"};
  DenoiseOptions raw = model.manifest().denoise;
  raw.mode = DenoiseMode::kRefiner;
  raw.refiner_blend = false;
  // The held-out clips as they are and played twice as slow (a slower style's motion: noise left
  // after denoising shows more against its smaller accelerations).
  Motions clips = data.held_out;
  const size_t as_recorded = clips.size();
  for (size_t q = 0; q < as_recorded; ++q) clips.push_back(SlowDown(clips[q], data.joints, 2.0));
  std::vector<Motions> noisy(kinds.size());
  for (size_t k = 0; k < kinds.size(); ++k) {
    std::mt19937_64 rng(seed + 4242 + k);
    noisy[k] = clips;
    if (!kinds[k].empty()) {
      const NoiseSpec spec = ParseNoiseSpec(kinds[k]);
      for (auto& q : noisy[k]) {
        AddNoise(spec, q.data(), static_cast<int>(q.size() / (3 * data.joints)), data.joints, rng);
      }
    }
  }
  std::vector<OutlierRepair> repairs = {OutlierRepair{}, {3, 3.0, false}, {3, 4.0, false}};
  for (int half : {3, 5})
    for (double deviations : {3.0, 4.0, 6.0}) repairs.push_back({half, deviations, true});
  RefinerBlend best;
  std::vector<Motions> inputs, refined;
  double least_log = INFINITY;
  for (const OutlierRepair& repair : repairs) {
    std::vector<Motions> in(kinds.size()), out(kinds.size());
    for (size_t k = 0; k < kinds.size(); ++k) {
      for (const auto& q : noisy[k]) in[k].push_back(RepairOutliers(q, data.joints, repair));
      out[k] = model.Denoise(in[k], raw);
    }
    for (Roughness roughness : {Roughness::kGaussian, Roughness::kSavitzkyGolay}) {
      RefinerBlend blend;
      double least = INFINITY;
      for (double sigma : {0.0, 0.5, 1.0, 1.5, 2.0}) {
        RefinerBlendFit fit(sigma, roughness);
        for (size_t k = 0; k < kinds.size(); ++k) fit.AddSetting(in[k], out[k], clips, data.joints);
        if (fit.Error() < least) {
          least = fit.Error();
          blend = fit.Blend();
        }
      }
      const double log_error = BlendKinds(in, out, clips, data.joints, blend);
      if (log_error < least_log) {
        least_log = log_error;
        best = blend;
        best.outliers = repair;
        inputs = in;
        refined = out;
      }
    }
  }
  // The output smoothing, fixed or chosen per motion (SmoothToAcceleration): the one of least
  // summed log error among those whose noisy outputs' acceleration is within kAccelRatioRange of
  // the clean clips' for every noisy kind at both speeds; where none is, the one of the least
  // largest |log(ratio)|.
  const auto accel_of = [&](const Motions& motions, size_t from, size_t to) {
    double sum = 0;
    for (size_t q = from; q < to; ++q) sum += MeanAcceleration(motions[q], data.joints, 1.0);
    return sum;
  };
  const double clean_accel[2] = {accel_of(clips, 0, as_recorded),
                                 accel_of(clips, as_recorded, clips.size())};
  // Each with the measure fitted and, for the Savitzky-Golay one, with its median over the joints
  // (the same weights): where the repair left an outlier here and there, the median does not call
  // the motion rough, and so does not smooth it, which spreads each outlier's error.
  std::vector<Roughness> measures = {best.roughness};
  if (best.roughness == Roughness::kSavitzkyGolay)
    measures.push_back(Roughness::kSavitzkyGolayMedian);
  std::vector<RefinerBlend> candidates;
  for (Roughness measure : measures) {
    RefinerBlend blend = best;
    blend.roughness = measure;
    for (double smooth : {0.0, 0.5, 0.75, 1.0, 1.5}) {
      candidates.push_back(blend);
      candidates.back().smooth = smooth;
    }
    for (double bound : {1.25, 1.5, 2.0, 2.5, 3.0, 4.0}) {
      candidates.push_back(blend);
      candidates.back().smooth = 0;
      candidates.back().accel_bound = bound;
    }
  }
  double least_misfit = INFINITY, least_error = INFINITY;
  for (const RefinerBlend& candidate : candidates) {
    std::vector<Motions> blended;
    const double log_error = BlendKinds(inputs, refined, clips, data.joints, candidate, &blended);
    double misfit = 0;  // the largest |log(ratio)|
    for (size_t k = 0; k < kinds.size(); ++k) {
      if (kinds[k].empty()) continue;
      for (int speed = 0; speed < 2; ++speed) {
        const double ratio =
            accel_of(blended[k], speed ? as_recorded : 0, speed ? clips.size() : as_recorded) /
            clean_accel[speed];
        misfit = std::max(misfit, std::abs(std::log(ratio)));
      }
    }
    const bool inside = misfit <= std::log(kAccelRatioRange);
    if (inside ? (least_misfit > std::log(kAccelRatioRange) || log_error < least_error)
               : (least_misfit > std::log(kAccelRatioRange) && misfit < least_misfit)) {
      best = candidate;
      least_error = log_error;
      least_misfit = misfit;
    }
  }
  return best;
}

}  // namespace

DvaeTrainSummary RefineDvae(const DvaeTrainConfig& config, const std::string& dvae_dir,
                            const DvaeData& data, const std::string& out_dir,
                            const DvaeTrainCallbacks& cb, int stop_after_epochs) {
  const DvaeRefinerConfig& rc = config.refiner;
  const RefinerTrainOptions& t = rc.training;
  DataParallel& workers = TrainingWorkers();
  PinThreads(workers.ThreadsPerWorker(t.threads));
  torch::manual_seed(t.seed);
  DvaeManifest m;
  const DvaeNet from = LoadDvaeBundle(dvae_dir, &m);
  const int W = rc.model.window, J = data.joints, F = 3 * J;
  if (DvaeValues(m) != F)
    throw std::invalid_argument(dvae_dir + ": the bundle's skeleton does not match the data's");
  m.refiner = rc.model;
  m.denoise.mode = DenoiseMode::kRefiner;
  SetManifestInfo(&m.info, "refiner_config", config.name);
  DvaeNet net = BuildDvaeNet(m);
  CopyTensorsByName(*from, *net);
  const DvaeTensors norm(m);
  const std::vector<torch::Tensor> trained = net->refiner->parameters();
  torch::optim::Adam adam(trained, torch::optim::AdamOptions(t.learning_rate));
  const std::vector<NoiseSpec> kinds = ParseNoiseSpecs(rc.noise);

  const fs::path out(out_dir);
  BestEpochRun run(out, "refiner_best.txt", "refiner_epoch");
  DvaeTrainSummary summary;
  summary.first_epoch = run.Resume(workers, net, adam, cb);
  // Held-out windows, the same every epoch: in turn Gaussian 2, 5 and 10 cm, outliers (10% of
  // joints, 30 cm), jitter 5 cm and clean (the evaluation's kinds).
  const WindowBatch held = HeldOutBatch(data, W, 1200);
  if (held.count == 0) {
    throw std::invalid_argument("refiner: no held-out clip has " + std::to_string(W) +
                                " frames (refiner.window)");
  }
  WindowBatch held_in, held_target;
  {
    const std::vector<NoiseSpec> held_kinds = ParseNoiseSpecs(
        {"gaussian:0.02", "gaussian:0.05", "gaussian:0.10", "outliers:0.1,0.3", "jitter:0.05"});
    std::mt19937_64 rng(t.seed + 99);
    std::vector<float> noisy;
    for (int64_t w = 0; w < held.count; ++w) {
      const float* clean = held.values.data() + w * W * F;
      noisy.assign(clean, clean + static_cast<size_t>(W) * F);
      if (w % 6 < 5) AddNoise(held_kinds[w % 6], noisy.data(), W, J, rng);
      AddWindowPair(clean, noisy, J, W, &held_in, &held_target);
    }
  }
  const std::vector<int> frames = ClipFrames(data.train, F);
  const int iterations = t.windows_per_epoch / t.batch_size, B = t.batch_size;
  workers.RequireBatch(B, "refiner.batch_size");
  const Share share = workers.BatchShare(B);
  const int Bs = static_cast<int>(share.size());
  const double weight = static_cast<double>(Bs) / B;
  const auto start = std::chrono::steady_clock::now();
  for (int epoch = summary.first_epoch; epoch < t.epochs; ++epoch) {
    if (stop_after_epochs > 0 && epoch - summary.first_epoch >= stop_after_epochs) break;
    if (run.Stalled(t.patience)) {
      summary.stopped_early = true;
      break;
    }
    const auto epoch_start = std::chrono::steady_clock::now();
    SetLearningRate(adam, t.learning_rate * std::pow(t.lr_decay, epoch));
    net->train();
    RandomWindowSampler sampler(frames, W, t.seed * 1000003ull + epoch);
    std::mt19937_64 rng(t.seed * 7919ull + epoch);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double sums[2] = {0, 0};
    std::vector<float> noisy;
    for (int it = 0; it < iterations; ++it) {
      WindowBatch input, target;
      for (int b = 0; b < B; ++b) {  // every window's noise drawn, this worker's share kept
        const Window w = sampler.Next();
        const float* clean = data.train[w.clip].data() + static_cast<size_t>(w.start) * F;
        noisy.assign(clean, clean + static_cast<size_t>(W) * F);
        if (unit(rng) >= rc.clean_share) AddNoise(RandomLevel(kinds, rng), noisy.data(), W, J, rng);
        if (b >= share.begin && b < share.end) AddWindowPair(clean, noisy, J, W, &input, &target);
      }
      const torch::Tensor y = norm.Normalise(input.values.data(), Bs, W);
      const torch::Tensor x = norm.Normalise(target.values.data(), Bs, W);
      const torch::Tensor loss = RefinerLoss(y + net->refiner(y), x, norm, J, rc.accel_weight);
      DataParallelStep(workers, adam, loss, trained, weight, t.grad_clip);
      AddStep<2>({loss, JointErrorCm(y, x, norm, J).detach()}, "Motion-DVAE refiner training",
                 epoch, it, iterations, cb, sums);
    }
    SumOverWorkers(workers, weight, sums);
    net->eval();
    double held_cm = 0, held_input_cm = 0, held_loss = 0;
    {
      torch::NoGradGuard no_grad;
      const torch::Tensor y = norm.Normalise(held_in.values.data(), held_in.count, W);
      const torch::Tensor x = norm.Normalise(held_target.values.data(), held_target.count, W);
      const torch::Tensor refined = y + net->refiner(y);
      held_cm = JointErrorCm(refined, x, norm, J).item<double>();
      held_loss = RefinerLoss(refined, x, norm, J, rc.accel_weight).item<double>();
      held_input_cm = JointErrorCm(y, x, norm, J).item<double>();
    }
    const DvaeEpochLog log =
        LogEpoch<2>(out / "log.csv", workers.writes(), epoch, 0.0, SecondsSince(epoch_start),
                    {"loss", "input_cm"}, sums, iterations,
                    {{"held_out_input_cm", held_input_cm},
                     {"held_out_refined_cm", held_cm},
                     {"held_out_loss", held_loss}});
    run.EndEpoch(workers, epoch, held_loss, &m, net, adam);
    summary.epochs_done = epoch + 1;
    if (cb.epoch) cb.epoch(log);
  }
  // The kept epoch's blend weights, fitted again whenever the command runs (a finished run too).
  if (workers.writes() && fs::exists(out / "dvae.yaml")) {
    DvaeManifest best;
    DvaeNet kept = LoadDvaeBundle(out_dir, &best);  // saved as loaded: the same weights file
    best.refiner_blend = FitRefinerBlend(LoadDvaeModel(out_dir), data, t.seed);
    SaveDvaeBundle(out_dir, best, kept);
    summary.refiner_blend = best.refiner_blend;
  }
  summary.seconds = SecondsSince(start);
  return summary;
}

DvaeTrainSummary RefitRefinerBlend(const DvaeTrainConfig& config, const std::string& dvae_dir,
                                   const DvaeData& data, const std::string& out_dir) {
  const auto start = std::chrono::steady_clock::now();
  DvaeManifest m;
  DvaeNet net = LoadDvaeBundle(dvae_dir, &m);
  if (!m.refiner.enabled() || m.denoise.mode != DenoiseMode::kRefiner) {
    throw std::invalid_argument(dvae_dir +
                                ": the bundle has no refiner whose blend could be fitted (train "
                                "one with 'dvae refine' without --blend-only)");
  }
  if (DvaeValues(m) != 3 * data.joints)
    throw std::invalid_argument(dvae_dir + ": the bundle's skeleton does not match the data's");
  // The fit runs the refiner without its blend: the bundle's own blend does not matter.
  m.refiner_blend = FitRefinerBlend(LoadDvaeModel(dvae_dir), data, config.refiner.training.seed);
  fs::create_directories(out_dir);
  SaveDvaeBundle(out_dir, m, net);
  DvaeTrainSummary summary;
  summary.refiner_blend = m.refiner_blend;
  summary.blend_only = true;
  summary.seconds = SecondsSince(start);
  return summary;
}

}  // namespace motionfork
