#include "flow/trainer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "flow/flow_module.h"
#include "io/file_util.h"
#include "launch/worker_place.h"
#include "torch_util/data_parallel.h"
#include "torch_util/threads.h"

namespace motionfork {
namespace {

constexpr const char* kCheckpointFormat = "motionfork-flow-prior-checkpoint";
constexpr int64_t kCheckpointVersion = 1;

uint64_t Fnv(const void* data, size_t bytes, uint64_t h = 1469598103934665603ull) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

// Identifies the training data: frame counts and a hash of every direction.
std::string DataFingerprint(const PriorData& d) {
  uint64_t h = Fnv(d.train.directions.data(), d.train.directions.size() * sizeof(float));
  h = Fnv(d.held_out.directions.data(), d.held_out.directions.size() * sizeof(float), h);
  char buf[128];
  std::snprintf(buf, sizeof(buf),
                "train %lld frames, held-out %lld frames, dim %d, fnv1a64:%016llx",
                static_cast<long long>(d.train.size()), static_cast<long long>(d.held_out.size()),
                d.train.dim, static_cast<unsigned long long>(h));
  return buf;
}

// Fisher-Yates with a 64-bit generator: the same order on every platform and standard library.
std::vector<int64_t> EpochOrder(int64_t n, uint64_t seed, int epoch) {
  std::vector<int64_t> order(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) order[i] = i;
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + static_cast<uint64_t>(epoch) + 1);
  for (int64_t i = n - 1; i > 0; --i)
    std::swap(order[i], order[rng() % static_cast<uint64_t>(i + 1)]);
  return order;
}

std::string FirstDifference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  while (true) {
    const bool ga = static_cast<bool>(std::getline(sa, la));
    const bool gb = static_cast<bool>(std::getline(sb, lb));
    if (!ga && !gb) return "";
    if (la != lb || ga != gb) return "'" + la + "' in the checkpoint, '" + lb + "' now";
  }
}

double Quantile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return std::nan("");
  return sorted[static_cast<size_t>(std::floor(p * (sorted.size() - 1)))];
}

struct CheckpointState {
  int epochs_done = 0;
  std::vector<double> train_nll, held_out_nll;
  double seconds = 0;
};

std::vector<double> ToVector(const torch::Tensor& t) {
  const torch::Tensor c = t.to(torch::kFloat64).contiguous();
  return std::vector<double>(c.data_ptr<double>(), c.data_ptr<double>() + c.numel());
}

void WriteCheckpoint(const std::string& path, const std::string& config_text,
                     const std::string& fingerprint, const CheckpointState& state,
                     const PoseFlow& flow, const torch::optim::Adam& adam) {
  torch::serialize::OutputArchive archive;
  archive.write("format", c10::IValue(std::string(kCheckpointFormat)));
  archive.write("version", c10::IValue(kCheckpointVersion));
  archive.write("config", c10::IValue(config_text));
  archive.write("data", c10::IValue(fingerprint));
  archive.write("epochs_done", c10::IValue(static_cast<int64_t>(state.epochs_done)));
  archive.write("seconds", c10::IValue(state.seconds));
  archive.write("train_nll", torch::tensor(state.train_nll, torch::kFloat64));
  archive.write("held_out_nll", torch::tensor(state.held_out_nll, torch::kFloat64));
  torch::serialize::OutputArchive model;
  flow->save(model);
  archive.write("model", model);
  torch::serialize::OutputArchive optimizer;
  adam.save(optimizer);
  archive.write("optimizer", optimizer);
  std::ostringstream out;
  archive.save_to(out);
  WriteFileAtomically(path, out.str());
}

CheckpointState ReadCheckpoint(const std::string& path, const std::string& config_text,
                               const std::string& fingerprint, PoseFlow& flow,
                               torch::optim::Adam& adam) {
  const std::string bytes = ReadFileBytes(path);
  torch::serialize::InputArchive archive;
  CheckpointState state;
  std::string config, data;
  try {
    archive.load_from(bytes.data(), bytes.size());
    c10::IValue v;
    archive.read("format", v);
    if (!v.isString() || v.toStringRef() != kCheckpointFormat)
      throw std::runtime_error("not a prior checkpoint");
    archive.read("version", v);
    if (v.toInt() != kCheckpointVersion) {
      throw std::runtime_error("version " + std::to_string(v.toInt()) + ", this build reads " +
                               std::to_string(kCheckpointVersion));
    }
    archive.read("config", v);
    config = v.toStringRef();
    archive.read("data", v);
    data = v.toStringRef();
    archive.read("epochs_done", v);
    state.epochs_done = static_cast<int>(v.toInt());
    archive.read("seconds", v);
    state.seconds = v.toDouble();
    torch::Tensor t;
    archive.read("train_nll", t);
    state.train_nll = ToVector(t);
    archive.read("held_out_nll", t);
    state.held_out_nll = ToVector(t);
  } catch (const std::exception& e) {
    throw FormatError(FormatMessage(
        path, "",
        std::string("unreadable prior checkpoint (") + e.what() + "); delete it to start over"));
  }
  if (config != config_text) {
    throw std::invalid_argument("checkpoint " + path + " was written with another config (" +
                                FirstDifference(config, config_text) +
                                "); train into a new folder, or restart to discard it");
  }
  if (data != fingerprint) {
    throw std::invalid_argument("checkpoint " + path + " was written for other data (" + data +
                                "; now " + fingerprint +
                                "); train into a new folder, or restart to discard it");
  }
  try {
    torch::serialize::InputArchive model, optimizer;
    archive.read("model", model);
    flow->load(model);
    archive.read("optimizer", optimizer);
    adam.load(optimizer);
  } catch (const std::exception& e) {
    throw FormatError(FormatMessage(
        path, "",
        std::string("unreadable prior checkpoint (") + e.what() + "); delete it to start over"));
  }
  return state;
}

}  // namespace

double PriorLearningRate(const PriorTrainOptions& o, int epoch) {
  if (epoch < o.constant_epochs) return o.learning_rate;
  const double decay =
      static_cast<double>(epoch - o.constant_epochs) / (o.epochs - o.constant_epochs + 1);
  return o.learning_rate * std::max(0.0, 1.0 - decay);
}

bool HeldOutStillFalling(const std::vector<double>& held_out_nll, double* gain) {
  const int n = static_cast<int>(held_out_nll.size());
  const int window = std::max(2, n / 10);
  if (gain) *gain = 0;
  if (n <= window || !std::isfinite(held_out_nll.back())) return false;
  double before = held_out_nll[0];
  for (int e = 1; e < n - window; ++e) before = std::min(before, held_out_nll[e]);
  const double g = before - held_out_nll.back();
  if (gain) *gain = g;
  return g > kPriorStillFallingNats;
}

double MeanNll(const PosePrior& prior, const PriorFrames& frames) {
  if (frames.size() == 0) return std::nan("");
  const std::vector<double> lp = prior.LogProbDirections(frames.directions);
  double sum = 0;
  for (double v : lp) sum -= v;
  return sum / static_cast<double>(lp.size());
}

PriorTrainOutcome TrainPosePrior(PosePrior& prior, const PriorData& data,
                                 const std::string& checkpoint_path,
                                 const PriorTrainCallbacks& callbacks) {
  const int64_t D = prior.dim();
  auto check_dim = [&](const PriorFrames& f, const char* what) {
    if (f.size() > 0 && f.dim != D) {
      throw std::invalid_argument(std::string("TrainPosePrior: ") + what + " frames have " +
                                  std::to_string(f.dim) + " numbers per pose, expected " +
                                  std::to_string(D) + " (the prior's skeleton)");
    }
  };
  check_dim(data.train, "training");
  check_dim(data.held_out, "held-out");
  check_dim(data.test, "test");
  if (data.train.size() == 0)
    throw std::invalid_argument("TrainPosePrior: expected training frames, got none");

  const auto run_start = std::chrono::steady_clock::now();
  auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  PriorTrainOutcome outcome;
  PoseFlow& flow = prior.module();
  flow->train();
  std::vector<torch::Tensor> params;
  for (const auto& p : flow->OrderedParameters()) params.push_back(p.second);
  // The schedule for this data's steps an epoch (at least min_steps in all).
  const int64_t N = data.train.size();
  const int64_t B = std::min<int64_t>(prior.config().training.batch_size, N);
  const int64_t steps = (N + B - 1) / B;
  const PriorSchedule schedule = MakePriorSchedule(prior.config().training, steps);
  PriorTrainOptions o = prior.config().training;
  o.epochs = schedule.epochs;
  o.constant_epochs = schedule.constant_epochs;
  outcome.epochs = schedule.epochs;
  outcome.epochs_raised = schedule.raised;
  torch::optim::Adam adam(params, torch::optim::AdamOptions(o.learning_rate)
                                      .betas({o.adam_beta1, o.adam_beta2})
                                      .eps(o.adam_eps)
                                      .weight_decay(o.weight_decay));

  const std::string config_text = FormatFlowConfig(prior.config());
  const std::string fingerprint = DataFingerprint(data);
  CheckpointState state;
  // Rank 0 reads the checkpoint; every worker takes its weights, Adam's state and epoch count.
  DataParallel& workers = TrainingWorkers();
  if (workers.distributed()) PinThreads(workers.ThreadsPerWorker(torch::get_num_threads()));
  if (workers.writes() && !checkpoint_path.empty() && std::filesystem::exists(checkpoint_path)) {
    state = ReadCheckpoint(checkpoint_path, config_text, fingerprint, flow, adam);
  }
  std::vector<double> resumed = {static_cast<double>(state.epochs_done)};
  workers.BroadcastTrainingState(*flow, adam, &resumed);
  state.epochs_done = static_cast<int>(resumed[0]);
  outcome.resumed_from_epoch = state.epochs_done;

  const torch::Tensor all =
      torch::from_blob(const_cast<float*>(data.train.directions.data()), {N, D}, torch::kFloat32);
  for (int epoch = state.epochs_done; epoch < o.epochs; ++epoch) {
    const auto epoch_start = std::chrono::steady_clock::now();
    PriorTrainProgress p;
    p.epoch = epoch;
    p.epochs = o.epochs;
    p.steps_per_epoch = steps;
    p.learning_rate = PriorLearningRate(o, epoch);
    for (auto& group : adam.param_groups()) {
      static_cast<torch::optim::AdamOptions&>(group.options()).lr(p.learning_rate);
    }
    std::vector<int64_t> order = EpochOrder(N, o.seed, epoch);
    const torch::Tensor order_t = torch::from_blob(order.data(), {N}, torch::kInt64);
    double nll_sum = 0;
    int64_t seen = 0;
    for (int64_t s = 0; s < steps; ++s) {
      // This worker's share of the step's frames; its gradient weighted by that share.
      const int64_t first = s * B, size = std::min(N, first + B) - first;
      const Share share = workers.BatchShare(size);
      const int64_t begin = first + share.begin, end = first + share.end;
      if (end == begin) {  // a last step with fewer frames than workers: this one has none
        adam.zero_grad();
        workers.ReduceGradients(params, 0.0);
        adam.step();
        continue;
      }
      const torch::Tensor batch = all.index_select(0, order_t.slice(0, begin, end));
      const torch::Tensor loss = -flow->log_prob(batch).mean();
      DataParallelStep(workers, adam, loss, params, static_cast<double>(end - begin) / size, 0);
      const double v = loss.item<double>();
      if (!std::isfinite(v)) {
        throw std::runtime_error("prior training diverged at epoch " + std::to_string(epoch + 1) +
                                 ", step " + std::to_string(s + 1) + " (NLL = " +
                                 std::to_string(v) + "); lower training.learning_rate");
      }
      nll_sum += v * (end - begin);
      seen += end - begin;
      p.step = s + 1;
      p.train_nll = nll_sum / seen;
      p.epoch_seconds = since(epoch_start);
      if (callbacks.progress) callbacks.progress(p);
      if (callbacks.stop_requested && callbacks.stop_requested()) {
        prior.mutable_summary().seconds = state.seconds + since(run_start);
        return outcome;
      }
    }
    if (workers.distributed()) {  // the epoch's mean over every worker's frames
      std::vector<double> totals = {nll_sum, static_cast<double>(seen)};
      workers.SumValues(&totals);
      p.train_nll = totals[0] / totals[1];
    }
    p.held_out_nll = MeanNll(prior, data.held_out);
    state.epochs_done = epoch + 1;
    state.train_nll.push_back(p.train_nll);
    state.held_out_nll.push_back(p.held_out_nll);
    const double before = state.seconds;
    state.seconds = before + since(run_start);
    if (workers.writes() && !checkpoint_path.empty()) {
      WriteCheckpoint(checkpoint_path, config_text, fingerprint, state, flow, adam);
    }
    state.seconds = before;  // this run's time is added once, at the end or on stop
    p.epoch_done = true;
    p.epoch_seconds = since(epoch_start);
    if (callbacks.progress) callbacks.progress(p);
  }
  flow->eval();

  PriorTrainingSummary& y = prior.mutable_summary();
  y.train_frames = N;
  y.held_out_frames = data.held_out.size();
  y.test_frames = data.test.size();
  y.epochs_completed = state.epochs_done;
  y.train_nll = state.train_nll;
  y.held_out_nll = state.held_out_nll;
  if (data.held_out.size() > 0) {
    std::vector<double> nll = prior.LogProbDirections(data.held_out.directions);
    for (double& v : nll) v = -v;
    std::sort(nll.begin(), nll.end());
    y.held_out_nll_q50 = Quantile(nll, 0.5);
    y.held_out_nll_q90 = Quantile(nll, 0.9);
    y.held_out_nll_q99 = Quantile(nll, 0.99);
  }
  y.test_nll = MeanNll(prior, data.test);
  outcome.still_falling = HeldOutStillFalling(state.held_out_nll, &outcome.recent_gain);
  y.seconds = state.seconds + since(run_start);
  if (!data.bone_lengths.empty()) prior.set_bone_lengths(data.bone_lengths);
  outcome.completed = true;
  return outcome;
}

}  // namespace motionfork
