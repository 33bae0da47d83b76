#include "imputation/training/hgvae_training.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include "bundle/hgvae_bundle.h"
#include "bundle/manifest.h"
#include "dataset/windows.h"
#include "imputation/gap_imputation.h"
#include "imputation/hgvae_model.h"
#include "imputation/hgvae_net.h"
#include "imputation/hgvae_tensors.h"
#include "imputation/refiner_fills.h"
#include "io/file_util.h"
#include "launch/worker_place.h"
#include "torch_util/checkpoint.h"
#include "torch_util/data_parallel.h"
#include "torch_util/parameters.h"
#include "torch_util/threads.h"
#include "torch_util/training_loop.h"

namespace motionfork {

namespace fs = std::filesystem;

HgvaeData MakeHgvaeData(const Dataset& dataset, const HgvaeTrainOptions& options, int window) {
  HgvaeData data;
  const HeldOutClips split = HoldOutTrainingClips(dataset, window, options.held_out_share,
                                                  options.seed, "HG-VAE training");
  const std::vector<int>& clips = split.clips;
  if (options.condition == "action") {
    std::set<std::string> names;
    for (int c : clips) names.insert(dataset.clips[c].action);
    data.classes.assign(names.begin(), names.end());
  }
  for (int c : clips) {
    const Clip& clip = dataset.clips[c];
    HgvaeClips& dst = split.held_out.count(c) ? data.held_out : data.train;
    dst.poses.push_back(PoseVectorsWithoutRoot(clip.motion));
    int label = -1;
    if (!data.classes.empty()) {
      label =
          static_cast<int>(std::lower_bound(data.classes.begin(), data.classes.end(), clip.action) -
                           data.classes.begin());
    }
    dst.labels.push_back(label);
  }
  data.coords = 3 * (dataset.clips[clips[0]].motion.num_joints() - 1);
  return data;
}

std::vector<float> HeldOutWindows(const HgvaeClips& clips, int window, int coords, int limit,
                                  std::vector<int>* labels) {
  std::vector<std::pair<int, int>> all;  // (clip, start)
  for (size_t c = 0; c < clips.poses.size(); ++c) {
    const int frames = static_cast<int>(clips.poses[c].size() / coords);
    for (int s = 0; s + window <= frames; ++s) all.emplace_back(static_cast<int>(c), s);
  }
  std::vector<std::pair<int, int>> picked;
  if (static_cast<int>(all.size()) <= limit) {
    picked = all;
  } else {
    for (int i = 0; i < limit; ++i)
      picked.push_back(all[static_cast<size_t>(i) * all.size() / limit]);
  }
  std::vector<float> out;
  out.reserve(picked.size() * window * coords);
  for (const auto& [c, s] : picked) {
    const float* p = clips.poses[c].data() + static_cast<size_t>(s) * coords;
    out.insert(out.end(), p, p + static_cast<size_t>(window) * coords);
    if (labels) labels->push_back(clips.labels[c]);
  }
  return out;
}

long long HgvaeData::train_frames() const {
  long long frames = 0;
  for (const auto& p : train.poses) frames += p.size() / coords;
  return frames;
}

namespace {

void ComputeNormalisation(const HgvaeClips& clips, int coords, HgvaeManifest* m) {
  std::vector<double> sum(coords, 0.0), sq(coords, 0.0);
  double frames = 0;
  for (const auto& p : clips.poses) {
    for (size_t i = 0; i < p.size(); ++i) {
      sum[i % coords] += p[i];
      sq[i % coords] += double(p[i]) * p[i];
    }
    frames += static_cast<double>(p.size() / coords);
  }
  m->mean.assign(coords, 0.0);
  m->std.assign(coords, 1.0);
  for (int c = 0; c < coords; ++c) {
    m->mean[c] = sum[c] / frames;
    m->std[c] = std::max(1e-3, std::sqrt(std::max(0.0, sq[c] / frames - m->mean[c] * m->mean[c])));
  }
}

// The OoD statistics of a bundle: mean and sample standard deviation of held-out windows' scores.
void SetScoreStatistics(const std::vector<double>& scores, HgvaeManifest* m) {
  double mean = 0, var = 0;
  for (double s : scores) mean += s;
  mean /= std::max<size_t>(1, scores.size());
  for (double s : scores) var += (s - mean) * (s - mean);
  m->score_mean = mean;
  m->score_std = std::sqrt(var / std::max<size_t>(1, scores.size() - 1));
}

}  // namespace

HgvaeTrainSummary TrainHgvae(const HgvaeTrainConfig& config, const HgvaeManifest& base,
                             const HgvaeData& data, const std::string& out_dir,
                             const HgvaeTrainCallbacks& cb, int stop_after_epochs) {
  const HgvaeTrainOptions& t = config.training;
  DataParallel& workers = TrainingWorkers();
  PinThreads(workers.ThreadsPerWorker(t.threads));
  torch::manual_seed(t.seed);
  HgvaeManifest m = base;
  m.model = config.model;
  m.classes = data.classes;
  const int N = data.coords, T = m.model.window;
  ComputeNormalisation(data.train, N, &m);
  const HgvaeTensors norm(m);
  HgvaeNet net = BuildHgvaeNet(m);
  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(t.learning_rate));
  const fs::path out(out_dir), ckpt = out / "checkpoint";
  HgvaeTrainSummary summary;
  std::vector<double> resumed = {0};
  if (workers.writes())
    resumed[0] = ResumeTraining(ckpt, "hgvae.pt", *net, adam, out / "log.csv", cb.message);
  workers.BroadcastTrainingState(*net, adam, &resumed);
  summary.first_epoch = static_cast<int>(resumed[0]);
  std::vector<int> frames;
  for (const auto& p : data.train.poses) frames.push_back(static_cast<int>(p.size() / N));
  const std::vector<float> held = HeldOutWindows(data.held_out, T, N, t.held_out_windows);
  const int64_t num_held = static_cast<int64_t>(held.size() / (static_cast<size_t>(T) * N));
  const int C = static_cast<int>(m.classes.size());
  const int iterations = t.windows_per_epoch / t.batch_size, B = t.batch_size;
  // This worker's share of every step's windows (all workers draw the whole step).
  workers.RequireBatch(B, "training.batch_size");
  const Share share = workers.BatchShare(B);
  const int Bs = static_cast<int>(share.size());
  const double weight = static_cast<double>(Bs) / B;
  double log_det = 0;  // normalised -> metres: log p_metres(x) = log p_norm(x) - T * sum log std
  for (double s : m.std) log_det += T * std::log(s);

  const auto start = std::chrono::steady_clock::now();
  for (int epoch = summary.first_epoch; epoch < t.epochs; ++epoch) {
    if (stop_after_epochs > 0 && epoch - summary.first_epoch >= stop_after_epochs) break;
    const auto epoch_start = std::chrono::steady_clock::now();
    net->train();
    RandomWindowSampler sampler(frames, T, t.seed * 1000003ull + epoch);
    std::mt19937_64 rng(t.seed * 7919ull + epoch);
    // The latents of each worker's share come from a generator of its own.
    at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(t.seed * 104729ull + epoch +
                                                                 1000000007ull * workers.rank());
    std::bernoulli_distribution drop(m.model.label_dropout);
    double sum_loss = 0, sum_nll = 0, sum_kl = 0, beta = 0;
    std::vector<double> sum_levels(net->num_levels(), 0.0);
    std::vector<float> batch(static_cast<size_t>(Bs) * T * N);
    for (int it = 0; it < iterations; ++it) {
      torch::Tensor labels;
      if (C > 0) labels = torch::zeros({Bs, C});
      for (int b = 0; b < B; ++b) {
        const Window w = sampler.Next();
        const bool labelled = C > 0 && !drop(rng);
        if (b < share.begin || b >= share.end) continue;
        const int i = b - static_cast<int>(share.begin);
        const float* p = data.train.poses[w.clip].data() + static_cast<size_t>(w.start) * N;
        std::copy(p, p + static_cast<size_t>(T) * N,
                  batch.begin() + static_cast<size_t>(i) * T * N);
        if (labelled) labels[i][data.train.labels[w.clip]] = 1.0f;
      }
      const torch::Tensor x = norm.ToNodeMajor(batch.data(), Bs);
      beta = AnnealedWeight(t.kl_start, t.kl_warmup_epochs,
                            epoch + static_cast<double>(it) / iterations);
      const HgvaeOutput o = net->forward(x, labels, LatentMode::kSample, gen);
      const torch::Tensor nll = -HgvaeNetImpl::GaussianLogLik(x, o.x_mean, o.x_logvar).mean();
      const torch::Tensor kl = o.kl.mean();
      const torch::Tensor loss = nll + beta * kl;
      DataParallelStep(workers, adam, loss, net->parameters(), weight, t.grad_clip);
      const double l = loss.item<double>(), n = nll.item<double>(), k = kl.item<double>();
      RequireFiniteLoss(l, "HG-VAE training", epoch);
      sum_loss += l;
      sum_nll += n;
      sum_kl += k;
      for (int64_t lv = 0; lv < net->num_levels(); ++lv)
        sum_levels[lv] += o.kl_levels[lv].mean().item<double>();
      if (cb.step)
        cb.step(epoch, double(it + 1) / iterations, sum_loss / (it + 1), sum_nll / (it + 1),
                sum_kl / (it + 1));
    }
    {  // the epoch's sums over every worker's share
      std::vector<double> totals = {sum_loss, sum_nll, sum_kl};
      totals.insert(totals.end(), sum_levels.begin(), sum_levels.end());
      for (double& v : totals) v *= weight;
      workers.SumValues(&totals);
      sum_loss = totals[0], sum_nll = totals[1], sum_kl = totals[2];
      std::copy(totals.begin() + 3, totals.end(), sum_levels.begin());
    }
    workers.AverageBuffers(*net);
    // Held-out figures (every worker computes them alike): ELBO (one posterior sample, fixed seed),
    // reconstruction MSE, posterior score.
    net->eval();
    double elbo = 0, mse = 0;
    std::vector<double> scores;
    {
      torch::NoGradGuard no_grad;
      at::Generator eval_gen = at::make_generator<at::CPUGeneratorImpl>(t.seed + 17);
      for (int64_t s = 0; s < num_held; s += 512) {
        const int64_t count = std::min<int64_t>(512, num_held - s);
        const torch::Tensor x =
            norm.ToNodeMajor(held.data() + static_cast<size_t>(s) * T * N, count);
        const HgvaeOutput o = net->forward(x, {}, LatentMode::kSample, eval_gen);
        elbo += (HgvaeNetImpl::GaussianLogLik(x, o.x_mean, o.x_logvar) - o.kl).sum().item<double>();
        const HgvaeOutput om = net->forward(x, {}, LatentMode::kPosteriorMean);
        mse += norm.SquaredErrorMetres(x, om.x_mean).sum().item<double>();
        const torch::Tensor sc = net->Score(x, om, m.ood_score);
        for (int64_t i = 0; i < count; ++i) scores.push_back(sc[i].item<double>());
      }
    }
    SetScoreStatistics(scores, &m);
    HgvaeEpochLog log;
    log.epoch = epoch;
    log.kl_weight = beta;
    log.seconds = SecondsSince(epoch_start);
    log.terms = {{"loss", sum_loss / iterations},
                 {"nll", sum_nll / iterations},
                 {"kl", sum_kl / iterations}};
    for (int64_t lv = 0; lv < net->num_levels(); ++lv) {
      log.terms.emplace_back("kl" + std::to_string(lv), sum_levels[lv] / iterations);
    }
    log.terms.emplace_back("held_out_elbo_nats", elbo / num_held - log_det);
    log.terms.emplace_back("held_out_mse_m2", mse / (static_cast<double>(num_held) * T * N));
    log.terms.emplace_back("held_out_score_mean", m.score_mean);
    log.terms.emplace_back("held_out_score_std", m.score_std);
    SetManifestInfo(&m.info, "epochs_trained", std::to_string(epoch + 1));
    if (workers.writes()) {
      AppendEpochLog(out / "log.csv", "kl_weight", epoch, beta, log.seconds, log.terms);
      SaveHgvaeBundle(out_dir, m, net);
      SaveCheckpoint(ckpt.string(), "hgvae.pt", *net, adam, epoch + 1);
    }
    summary.epochs_done = epoch + 1;
    if (cb.epoch) cb.epoch(log);
  }
  summary.seconds = SecondsSince(start);
  return summary;
}

void RefreshBundleSettings(const std::string& dir, const HgvaeData& data,
                           const HgvaeTrainConfig& config) {
  const HgvaeModel model = LoadHgvaeModel(dir);
  const std::vector<float> held = HeldOutWindows(data.held_out, model.window(), model.coords(),
                                                 config.training.held_out_windows);
  HgvaeManifest m = model.manifest();
  SetScoreStatistics(model.Score(held, config.ood_score), &m);
  m.ood_score = config.ood_score;
  m.ood_k = config.ood_k;
  if (config.impute.start != ImputeStart::kRefiner || m.refiner.enabled()) m.impute = config.impute;
  RewriteHgvaeManifest(dir, m);
}

}  // namespace motionfork

namespace motionfork {

namespace {

// A random mask [W, J, 3] (1 = missing) of a kind users meet: values at random (0.5-95%), or a
// gap (1 frame to the whole window) of one joint, a joint and everything below it, or one of the
// skeleton's standard groups (a hand, an arm, the legs, the upper body).
std::vector<uint8_t> RandomMask(const Skeleton& skeleton,
                                const std::vector<std::vector<int>>& groups, int W,
                                std::mt19937_64& rng) {
  const int J = skeleton.num_joints();
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  GapSetting s;
  const int kind = static_cast<int>(rng() % 4);
  if (kind == 0) {
    s.share = 0.005 + 0.945 * unit(rng);
  } else if (kind == 3 && !groups.empty()) {
    s.joints = groups[rng() % groups.size()];
  } else {
    const int j = 1 + static_cast<int>(rng() % (J - 1));
    s.joints = {j};
    for (int k = j + 1; kind == 2 && k < J; ++k) {  // descendants come after their parent
      for (int a = skeleton.parent(k); a > 0; a = skeleton.parent(a)) {
        if (a == j) {
          s.joints.push_back(k);
          break;
        }
      }
    }
  }
  if (s.share == 0 && unit(rng) < 0.8) s.gap_frames = 1 + static_cast<int>(rng() % (W - 2));
  std::vector<uint8_t> mask = GapMask(s, W, J, rng());
  if (mask.empty()) {  // the gap did not fit bracketed: the whole window
    s.gap_frames = 0;
    mask = GapMask(s, W, J, rng());
  }
  return mask;
}

// A batch of refiner examples: clean root-relative windows [B, W, N], their fills and masks.
struct RefinerBatch {
  std::vector<float> clean;
  RefinerFills fills;
  int64_t count = 0;
};

void AddRefinerExample(const Skeleton& skeleton, const std::vector<float>& fallback,
                       const float* poses, int W, const std::vector<uint8_t>& mask,
                       RefinerBatch* b) {
  const int J = skeleton.num_joints(), N = 3 * (J - 1);
  const RefinerFills f = MakeRefinerFills(skeleton, WithRootAtOrigin(poses, W, N), mask, fallback);
  b->clean.insert(b->clean.end(), poses, poses + static_cast<size_t>(W) * N);
  AppendRefinerFills(f, &b->fills);
  ++b->count;
}

// Per window, the mean squared error of the missing values in cm^2 of the refined windows
// (spline + correction) and of the spline: [B] each.
std::pair<torch::Tensor, torch::Tensor> MissingErrors(HgvaeNet& net, const HgvaeTensors& norm,
                                                      const RefinerBatch& b, int W) {
  const torch::Tensor in = norm.RefinerInput(b.fills);
  const int64_t N = norm.coords();
  const torch::Tensor spline = norm.RefinerPart(in, HgvaeTensors::RefinerChannels::kSpline);
  const torch::Tensor refined = norm.DenormaliseFrameMajor(norm.Refined(in, net->refiner(in)));
  const torch::Tensor clean = torch::from_blob(const_cast<float*>(b.clean.data()), {b.count, W, N});
  const torch::Tensor mask = norm.RefinerPart(in, HgvaeTensors::RefinerChannels::kMask);
  const torch::Tensor count = mask.sum({1, 2}).clamp_min(1);
  auto mse = [&](const torch::Tensor& x) {
    return ((x - clean) * 100).pow(2).mul(mask).sum({1, 2}) / count;
  };
  return {mse(refined), mse(norm.DenormaliseFrameMajor(spline)).detach()};
}

// The refiner's loss: the mean over windows of log(refined + e) - log(spline + e), e = (0.05
// cm)^2: every window counts by its improvement on the spline, short gaps (where the spline is
// right to a millimetre) as much as long ones.
torch::Tensor RelativeLoss(const std::pair<torch::Tensor, torch::Tensor>& errors) {
  constexpr double kFloor = 0.0025;
  return (torch::log(errors.first + kFloor) - torch::log(errors.second + kFloor)).mean();
}

}  // namespace

HgvaeTrainSummary RefineHgvae(const HgvaeTrainConfig& config, const std::string& hgvae_dir,
                              const HgvaeData& data, const std::string& out_dir,
                              const HgvaeRefineCallbacks& cb, int stop_after_epochs) {
  const RefinerTrainOptions& t = config.refiner.training;
  DataParallel& workers = TrainingWorkers();
  PinThreads(workers.ThreadsPerWorker(t.threads));
  torch::manual_seed(t.seed);
  HgvaeManifest m;
  const HgvaeNet from = LoadHgvaeBundle(hgvae_dir, &m);
  const int W = config.refiner.model.window, N = data.coords;
  if (HgvaeCoords(m) != N)
    throw std::invalid_argument(hgvae_dir + ": the bundle's skeleton does not match the data's");
  m.refiner = config.refiner.model;
  m.impute.start = ImputeStart::kRefiner;
  m.impute.steps = 0;
  SetManifestInfo(&m.info, "refiner_config", config.name);
  HgvaeNet net = BuildHgvaeNet(m);
  CopyTensorsByName(*from, *net);
  const HgvaeTensors norm(m);
  const Skeleton skeleton = Skeleton::Build(m.skeleton);
  std::vector<float> fallback(3 + m.mean.size(), 0.0f);
  for (size_t v = 0; v < m.mean.size(); ++v) fallback[3 + v] = static_cast<float>(m.mean[v]);
  std::vector<std::vector<int>> groups;
  for (const GapSetting& s : StandardGapSettings(skeleton, m.fps))
    if (s.share == 0 && s.gap_frames == 0) groups.push_back(s.joints);
  const std::vector<torch::Tensor> trained = net->refiner->parameters();
  torch::optim::Adam adam(trained, torch::optim::AdamOptions(t.learning_rate));

  const fs::path out(out_dir), ckpt = out / "checkpoint", state = ckpt / "refiner_best.txt";
  HgvaeTrainSummary summary;
  std::vector<double> resumed = {0, INFINITY, 0};  // epochs done, best held-out loss, bad epochs
  if (workers.writes()) {
    resumed[0] = ResumeTraining(ckpt, "hgvae.pt", *net, adam, out / "log.csv", cb.message);
    if (resumed[0] > 0) {
      std::ifstream in(state);
      in >> resumed[1] >> resumed[2];
    }
  }
  workers.BroadcastTrainingState(*net, adam, &resumed);
  summary.first_epoch = static_cast<int>(resumed[0]);
  double best = resumed[1];
  int bad_epochs = static_cast<int>(resumed[2]);

  // Held-out examples, the same every epoch: windows of the held-out clips every W frames.
  RefinerBatch held;
  {
    std::mt19937_64 rng(t.seed + 99);
    for (const auto& clip : data.held_out.poses) {
      const int frames = static_cast<int>(clip.size() / N);
      for (int s = 0; s + W <= frames && held.count < 600; s += W) {
        AddRefinerExample(skeleton, fallback, clip.data() + static_cast<size_t>(s) * N, W,
                          RandomMask(skeleton, groups, W, rng), &held);
      }
    }
  }
  if (held.count == 0) {
    throw std::invalid_argument("refiner: no held-out clip has " + std::to_string(W) +
                                " frames (refiner.window)");
  }
  std::vector<int> frames;
  for (const auto& clip : data.train.poses) frames.push_back(static_cast<int>(clip.size() / N));
  const int iterations = t.windows_per_epoch / t.batch_size, B = t.batch_size;
  workers.RequireBatch(B, "refiner.batch_size");
  const Share share = workers.BatchShare(B);
  const double weight = static_cast<double>(share.size()) / B;
  const auto start = std::chrono::steady_clock::now();
  for (int epoch = summary.first_epoch; epoch < t.epochs; ++epoch) {
    if (stop_after_epochs > 0 && epoch - summary.first_epoch >= stop_after_epochs) break;
    if (bad_epochs >= t.patience) break;
    const auto epoch_start = std::chrono::steady_clock::now();
    SetLearningRate(adam, t.learning_rate * std::pow(t.lr_decay, epoch));
    net->train();
    RandomWindowSampler sampler(frames, W, t.seed * 1000003ull + epoch);
    std::mt19937_64 rng(t.seed * 7919ull + epoch);
    std::vector<double> sums = {0, 0, 0};  // loss, refined and spline MSE (cm^2)
    for (int it = 0; it < iterations; ++it) {
      RefinerBatch batch;
      for (int b = 0; b < B; ++b) {  // every window's mask drawn, this worker's share kept
        const Window w = sampler.Next();
        const std::vector<uint8_t> mask = RandomMask(skeleton, groups, W, rng);
        if (b >= share.begin && b < share.end) {
          AddRefinerExample(skeleton, fallback,
                            data.train.poses[w.clip].data() + static_cast<size_t>(w.start) * N, W,
                            mask, &batch);
        }
      }
      const auto errors = MissingErrors(net, norm, batch, W);
      const torch::Tensor loss = RelativeLoss(errors);
      DataParallelStep(workers, adam, loss, trained, weight, t.grad_clip);
      const double l = loss.item<double>();
      RequireFiniteLoss(l, "HG-VAE refiner training", epoch);
      sums[0] += l;
      sums[1] += errors.first.mean().item<double>();
      sums[2] += errors.second.mean().item<double>();
      if (cb.step) cb.step(epoch, double(it + 1) / iterations, sums[0] / (it + 1));
    }
    for (double& v : sums) v *= weight;
    workers.SumValues(&sums);
    net->eval();
    double held_loss = 0, held_refined = 0, held_spline = 0;
    {
      torch::NoGradGuard no_grad;
      const auto errors = MissingErrors(net, norm, held, W);
      held_loss = RelativeLoss(errors).item<double>();
      held_refined = std::sqrt(errors.first.mean().item<double>());
      held_spline = std::sqrt(errors.second.mean().item<double>());
    }
    HgvaeEpochLog log;
    log.epoch = epoch;
    log.seconds = SecondsSince(epoch_start);
    log.terms = {{"loss", sums[0] / iterations},
                 {"refined_rms_cm", std::sqrt(sums[1] / iterations)},
                 {"spline_rms_cm", std::sqrt(sums[2] / iterations)},
                 {"held_out_loss", held_loss},
                 {"held_out_refined_rms_cm", held_refined},
                 {"held_out_spline_rms_cm", held_spline}};
    if (workers.writes())
      AppendEpochLog(out / "log.csv", "kl_weight", epoch, 0.0, log.seconds, log.terms);
    if (held_loss < best) {
      best = held_loss;
      bad_epochs = 0;
      SetManifestInfo(&m.info, "refiner_epoch", std::to_string(epoch + 1));
      if (workers.writes()) SaveHgvaeBundle(out_dir, m, net);
    } else {
      ++bad_epochs;
    }
    std::ostringstream st;
    st.precision(17);
    st << best << " " << bad_epochs << "\n";
    if (workers.writes()) {
      SaveCheckpoint(ckpt.string(), "hgvae.pt", *net, adam, epoch + 1,
                     {{state.filename().string(), st.str()}});
    }
    summary.epochs_done = epoch + 1;
    if (cb.epoch) cb.epoch(log);
  }
  summary.seconds = SecondsSince(start);
  return summary;
}

}  // namespace motionfork
