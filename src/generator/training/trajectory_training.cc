#include "generator/training/trajectory_training.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>
#include <stdexcept>

#include "bodyparts/part_plan.h"
#include "bundle/bundle_files.h"
#include "bundle/trajectory_bundle.h"
#include "config/rig_config.h"
#include "core/heading.h"
#include "dataset/windows.h"
#include "generator/trajectory/trajectory_net.h"
#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

namespace {

// The windows of the training clips and how to bring one into the body's frame.
struct WindowSource {
  std::vector<const Motion*> clips;
  std::vector<Window> train, validation;
  int t_his = 0, t_pred = 0, joints = 0;
  UpAxis up;
  HeadingJoints heading;  // node indices

  // poses [B, T, N, 3] root-relative and roots [B, T, 3] relative to the last history root, both
  // turned so that the last history frame faces one way.
  void Gather(const std::vector<Window>& windows, size_t first, size_t count, torch::Tensor* poses,
              torch::Tensor* roots) const {
    const int T = t_his + t_pred, N = joints - 1;
    *poses = torch::empty({static_cast<int64_t>(count), T, N, 3});
    *roots = torch::empty({static_cast<int64_t>(count), T, 3});
    for (size_t i = 0; i < count; ++i) {
      const Window& w = windows[first + i];
      const Motion& m = *clips[w.clip];
      float* p = poses->data_ptr<float>() + i * T * N * 3;
      float* r = roots->data_ptr<float>() + i * T * 3;
      const float* last = m.frame(w.start + t_his - 1);
      for (int t = 0; t < T; ++t) {
        const float* fr = m.frame(w.start + t);
        for (int a = 0; a < 3; ++a) r[3 * t + a] = fr[a] - last[a];
        for (int j = 1; j < joints; ++j)
          for (int a = 0; a < 3; ++a) p[(t * N + j - 1) * 3 + a] = fr[3 * j + a] - fr[a];
      }
      RotateAboutUp(r, T, TurnToBodyFrame(p, T, N, t_his, heading, up), up);
    }
  }
};

struct LossParts {
  torch::Tensor total, root, final, skating;
};

// pred [B, t_pred, 3], the window's true poses [B, T, N, 3] and roots [B, T, 3].
LossParts Losses(const torch::Tensor& pred, const torch::Tensor& poses, const torch::Tensor& roots,
                 const WindowSource& src, const std::vector<int64_t>& feet,
                 const TrajectoryTrainOptions& o) {
  const int64_t th = src.t_his;
  const torch::Tensor truth = roots.slice(1, th);
  auto distance = [](const torch::Tensor& d) { return (d.pow(2).sum(-1) + 1e-10).sqrt(); };
  LossParts l;
  l.root = distance(pred - truth).mean();
  l.final = distance(pred.select(1, -1) - truth.select(1, -1)).mean();
  l.total = l.root + o.final_weight * l.final;
  if (feet.empty() || o.skating_weight == 0) {
    l.skating = torch::zeros({});
    return l;
  }
  const torch::Tensor idx = torch::tensor(feet);
  const torch::Tensor rel = poses.index_select(2, idx);                     // [B, T, F, 3]
  const torch::Tensor world = rel + roots.unsqueeze(2);                     // true feet
  const torch::Tensor height = world.select(3, src.up.axis) * src.up.sign;  // [B, T, F]
  const torch::Tensor ground = std::get<0>(height.flatten(1).min(1)).view({-1, 1, 1});
  const torch::Tensor h = height.slice(1, th - 1) - ground;  // [B, t_pred + 1, F]
  const torch::Tensor high = torch::max(h.slice(1, 0, -1), h.slice(1, 1));
  const torch::Tensor weight =
      (2.0 - torch::pow(2.0, high / o.contact_height)).clamp(0.0, 1.0);  // [B, t_pred, F]
  const torch::Tensor path =
      torch::cat({torch::zeros({pred.size(0), 1, 3}), pred}, 1).unsqueeze(2);  // from the last
  const torch::Tensor feet_pred = rel.slice(1, th - 1) + path;  // [B, t_pred+1, F, 3]
  const torch::Tensor step = feet_pred.slice(1, 1) - feet_pred.slice(1, 0, -1);
  const auto [a, b] = GroundAxes(src.up);
  const torch::Tensor slide = (step.select(3, a).pow(2) + step.select(3, b).pow(2) + 1e-10).sqrt();
  l.skating = (weight * slide).sum({1, 2}).mean() / static_cast<double>(src.t_pred);
  l.total = l.total + o.skating_weight * l.skating;
  return l;
}

double LearningRate(const TrajectoryTrainOptions& o, int epoch) {
  if (epoch < o.lr_constant_epochs) return o.learning_rate;
  return o.learning_rate * (1.0 - static_cast<double>(epoch - o.lr_constant_epochs) /
                                      (o.epochs - o.lr_constant_epochs + 1));
}

}  // namespace

TrajectoryTrainSummary TrainTrajectory(const TrajectoryTrainOptions& o, const ModelConfig& model,
                                       const Dataset& ds, const std::vector<int>& feet,
                                       const std::string& out_dir, const TrainCallbacks& cb) {
  const GeneratorOptions& g = model.generator;
  if (g.body_frame.empty()) {
    throw std::invalid_argument(
        "trajectory: the generator predicts in the data's axes; train it with "
        "generator.body_frame: true first");
  }
  const Skeleton skeleton = Skeleton::Build(model.skeleton);
  const PartPlan plan = MakePartPlan(skeleton, g.partition);
  WindowSource src;
  src.t_his = g.t_his;
  src.t_pred = g.t_pred;
  src.joints = skeleton.num_joints();
  src.up = ParseUp(g.body_frame);
  src.heading = HeadingNodes(skeleton);
  const std::vector<int> train = ds.ClipIndices(Split::kTrain);
  for (int c : train) src.clips.push_back(&ds.clips[c].motion);
  for (const Window& w : SlidingWindows(ds.ClipFrames(train), g.num_frames(), o.window_stride,
                                        /*include_last=*/true)) {
    const bool held =
        o.validation_every > 0 && w.clip % o.validation_every == o.validation_every - 1;
    (held ? src.validation : src.train).push_back(w);
  }
  if (src.train.size() < static_cast<size_t>(o.batch)) {
    throw std::invalid_argument("trajectory: " + std::to_string(src.train.size()) +
                                " training windows, fewer than a batch of " +
                                std::to_string(o.batch));
  }
  std::vector<int64_t> feet_nodes;
  for (int f : feet) feet_nodes.push_back(f - 1);

  TrajectoryManifest m;
  m.protocol = model.protocol;
  m.fps = model.fps;
  TrajectoryOptions& to = m.options;
  to.t_his = g.t_his;
  to.t_pred = g.t_pred;
  to.num_nodes = g.num_nodes;
  to.future_nodes = plan.nodes.front();
  to.n_in = o.n_in > 0 ? o.n_in : g.n_pre;
  to.n_out = o.n_out;
  to.hidden = o.hidden;
  to.layers = o.layers;
  to.up = g.body_frame;
  torch::manual_seed(o.seed);
  TrajectoryNet net(to);

  // Standardisation from (up to) 20,000 training windows spread over the split.
  {
    const size_t n = std::min<size_t>(src.train.size(), 20000);
    std::vector<Window> sample;
    for (size_t i = 0; i < n; ++i) sample.push_back(src.train[i * src.train.size() / n]);
    torch::Tensor poses, roots;
    src.Gather(sample, 0, n, &poses, &roots);
    torch::NoGradGuard no_grad;
    net->SetStatistics(net->Features(poses, roots.slice(1, 0, g.t_his)),
                       net->StepCoefficients(roots.slice(1, g.t_his)));
  }

  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(o.learning_rate));
  TrajectoryTrainSummary summary;
  summary.train_windows = src.train.size();
  summary.validation_windows = src.validation.size();
  std::vector<torch::Tensor> best;  // the kept epoch's parameters and buffers
  double best_fde = INFINITY;
  std::ostringstream log;
  log << "epoch,lr,seconds,loss,root,final,skating,val_ade,val_fde\n";
  const auto start = std::chrono::steady_clock::now();
  std::vector<Window> order = src.train;
  const size_t steps = order.size() / o.batch;
  for (int epoch = 0; epoch < o.epochs; ++epoch) {
    const auto epoch_start = std::chrono::steady_clock::now();
    const double lr = LearningRate(o, epoch);
    for (auto& group : adam.param_groups())
      static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
    std::mt19937_64 rng(o.seed * 1000003ull + epoch);
    std::shuffle(order.begin(), order.end(), rng);
    net->train();
    double sums[4] = {0, 0, 0, 0};
    for (size_t s = 0; s < steps; ++s) {
      torch::Tensor poses, roots;
      src.Gather(order, s * o.batch, o.batch, &poses, &roots);
      const torch::Tensor pred = net->forward(poses, roots.slice(1, 0, g.t_his));
      const LossParts l = Losses(pred, poses, roots, src, feet_nodes, o);
      adam.zero_grad();
      l.total.backward();
      adam.step();
      sums[0] += l.total.item<double>();
      sums[1] += l.root.item<double>();
      sums[2] += l.final.item<double>();
      sums[3] += l.skating.item<double>();
      if (cb.step) {
        const double k = static_cast<double>(s + 1);
        cb.step(epoch, k / steps,
                {{"loss", sums[0] / k},
                 {"root", sums[1] / k},
                 {"final", sums[2] / k},
                 {"skating", sums[3] / k}});
      }
    }
    double val_ade = 0, val_fde = 0;
    if (!src.validation.empty()) {
      net->eval();
      torch::NoGradGuard no_grad;
      for (size_t first = 0; first < src.validation.size(); first += 1024) {
        const size_t n = std::min<size_t>(1024, src.validation.size() - first);
        torch::Tensor poses, roots;
        src.Gather(src.validation, first, n, &poses, &roots);
        const torch::Tensor d =
            (net->forward(poses, roots.slice(1, 0, g.t_his)) - roots.slice(1, g.t_his))
                .norm(2, -1);  // [n, t_pred]
        val_ade += d.mean(1).sum().item<double>();
        val_fde += d.select(1, -1).sum().item<double>();
      }
      val_ade /= src.validation.size();
      val_fde /= src.validation.size();
    }
    const bool keep = src.validation.empty() || val_fde < best_fde;
    if (keep) {
      best_fde = val_fde;
      summary.kept_epoch = epoch + 1;
      summary.val_ade = val_ade;
      summary.val_fde = val_fde;
      best.clear();
      for (const auto& p : net->parameters()) best.push_back(p.detach().clone());
      for (const auto& b : net->buffers()) best.push_back(b.detach().clone());
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - epoch_start).count();
    const std::vector<std::pair<std::string, double>> terms = {
        {"loss", sums[0] / steps},    {"root", sums[1] / steps}, {"final", sums[2] / steps},
        {"skating", sums[3] / steps}, {"val_ade", val_ade},      {"val_fde", val_fde}};
    log << epoch + 1 << "," << lr << "," << seconds;
    for (const auto& [name, v] : terms) log << "," << v;
    log << "\n";
    if (cb.epoch) cb.epoch(epoch, terms, seconds);
  }
  {
    torch::NoGradGuard no_grad;
    size_t i = 0;
    for (auto& p : net->parameters()) p.copy_(best[i++]);
    for (auto& b : net->buffers()) b.copy_(best[i++]);
  }
  net->eval();
  m.info["epochs"] = std::to_string(o.epochs);
  m.info["kept_epoch"] = std::to_string(summary.kept_epoch);
  m.info["train_windows"] = std::to_string(summary.train_windows);
  m.info["validation_windows"] = std::to_string(summary.validation_windows);
  m.info["validation_root_ade"] = std::to_string(summary.val_ade);
  m.info["validation_root_fde"] = std::to_string(summary.val_fde);
  m.info["seed"] = std::to_string(o.seed);
  const fs::path dir = fs::path(out_dir) / kTrajectoryFolder;
  SaveTrajectoryBundle(dir.string(), m, net);
  WriteFileAtomically((dir / "log.csv").string(), log.str());
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

bool TrajectoryTrained(const std::string& out_dir) {
  return fs::is_regular_file(fs::path(out_dir) / kTrajectoryFolder / "trajectory.yaml");
}

std::string TrajectoryDoneText(const TrajectoryTrainSummary& s, const std::string& out_dir) {
  char line[400];
  std::snprintf(line, sizeof(line),
                "trajectory: %zu training windows, %zu held out; kept epoch %d (validation root "
                "ADE %.3f m, FDE %.3f m); %.0f s; wrote %s\n",
                s.train_windows, s.validation_windows, s.kept_epoch, s.val_ade, s.val_fde,
                s.seconds, (fs::path(out_dir) / kTrajectoryFolder).string().c_str());
  return line;
}

std::string TrainTrajectoryOnce(const TrajectoryTrainOptions& options, const ModelConfig& model,
                                const Dataset& ds, const std::string& config_dir,
                                const std::string& out_dir, const TrainCallbacks& callbacks) {
  if (TrajectoryTrained(out_dir))
    return "trajectory: " + out_dir + "/" + kTrajectoryFolder + " already trained\n";
  const std::vector<int> feet = AnkleJoints(*ds.skeleton.skeleton, config_dir);
  return TrajectoryDoneText(TrainTrajectory(options, model, ds, feet, out_dir, callbacks), out_dir);
}

}  // namespace motionfork
