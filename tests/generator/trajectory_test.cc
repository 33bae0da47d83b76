// Where the root goes (issue 27): the trajectory network, its bundle, its training, and the
// Forecaster predicting in the body's frame (turning and moving a history turns and moves every
// future alike).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "bundle/generator_bundle.h"
#include "bundle/trajectory_bundle.h"
#include "core/heading.h"
#include "generator/inference/forecaster.h"
#include "generator/training/trajectory_training.h"
#include "generator/trajectory/trajectory_net.h"
#include "synthetic_training.h"
#include "test_support.h"
#include "torch_catch.h"

using namespace motionfork;

namespace {

TrajectoryOptions SmallOptions() {
  TrajectoryOptions o;
  o.t_his = 5;
  o.t_pred = 10;
  o.num_nodes = 16;
  o.future_nodes = {0, 1, 2, 3, 4, 5};
  o.n_in = 6;
  o.n_out = 4;
  o.hidden = 16;
  o.layers = 2;
  return o;
}

// A network whose output layer is not zero (a fresh one predicts the mean).
TrajectoryNet RandomNet(const TrajectoryOptions& o) {
  torch::manual_seed(3);
  TrajectoryNet net(o);
  torch::NoGradGuard no_grad;
  for (auto& p : net->parameters()) p.normal_(0, 0.3);
  net->eval();
  return net;
}

// Synthetic walks, clip c turned by 0.9 c radians about Y: the walking direction differs per clip.
Dataset TurnedWalks(int clips, int frames) {
  Dataset ds = testing::SyntheticDataset(clips, frames);
  for (int c = 0; c < clips; ++c) {
    Motion& m = ds.clips[c].motion;
    std::vector<float> p = m.positions();
    RotateAboutUp(p.data(), p.size() / 3, 0.9 * c, UpAxis{1, 1});
    m = Motion(m.skeleton_ptr(), m.fps(), std::move(p));
  }
  return ds;
}

}  // namespace

TEST_CASE("the trajectory reads the history and its future nodes' futures only") {
  const TrajectoryOptions o = SmallOptions();
  TrajectoryNet net = RandomNet(o);
  torch::NoGradGuard no_grad;
  const torch::Tensor poses = torch::randn({2, 15, 16, 3}) * 0.3;
  const torch::Tensor roots = torch::randn({2, 5, 3}) * 0.1;
  const torch::Tensor y = net->forward(poses, roots);
  REQUIRE(y.sizes() == torch::IntArrayRef({2, 10, 3}));
  torch::Tensor other = poses.clone();
  other.slice(1, 5).select(2, 10) += 0.5;  // a node outside the future nodes, future frames
  CHECK(torch::equal(net->forward(other, roots), y));
  other = poses.clone();
  other.slice(1, 5).select(2, 2) += 0.5;  // a future node
  CHECK_FALSE(torch::allclose(net->forward(other, roots), y));
  other = poses.clone();
  other.slice(1, 0, 5).select(2, 10) += 0.5;  // any node's history
  CHECK_FALSE(torch::allclose(net->forward(other, roots), y));
  CHECK_THROWS_WITH(net->forward(poses.slice(1, 1), roots), Catch::Contains("expected poses"));
}

TEST_CASE("trajectory bundles load what was saved and refuse edited manifests") {
  testing::TempDir dir;
  TrajectoryManifest m;
  m.protocol = "synthetic";
  m.fps = 30;
  m.options = SmallOptions();
  TrajectoryNet net = RandomNet(m.options);
  SaveTrajectoryBundle(dir.path().string(), m, net);
  TrajectoryManifest back;
  TrajectoryNet loaded = LoadTrajectoryBundle(dir.path().string(), &back);
  CHECK(back.options.future_nodes == m.options.future_nodes);
  CHECK(back.options.up == "y");
  torch::NoGradGuard no_grad;
  const torch::Tensor poses = torch::randn({3, 15, 16, 3});
  const torch::Tensor roots = torch::randn({3, 5, 3});
  CHECK(torch::equal(loaded->forward(poses, roots), net->forward(poses, roots)));
  // An edited size no longer describes the weights.
  const auto yaml = dir.path() / "trajectory.yaml";
  std::ifstream in(yaml);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  in.close();
  text.replace(text.find("hidden: 16"), 10, "hidden: 17");
  std::ofstream(yaml) << text;
  CHECK_THROWS_WITH(LoadTrajectoryBundle(dir.path().string(), &back),
                    Catch::Contains("trajectory.pt"));
}

TEST_CASE("trained on walks in every direction, futures walk on and turn with their history") {
  testing::TempDir out;
  const Dataset ds = TurnedWalks(8, 60);
  GeneratorTrainConfig cfg = testing::TinyConfig();
  cfg.body_frame = true;
  ModelConfig model = testing::ModelFor(ds, cfg);
  model.generator.body_frame = "y";
  const TrainingWindows data =
      BuildTrainingWindows(ds, 2, cfg.multimodal, model.generator.body_frame, "");
  CHECK_THROWS_WITH(TrainGenerator(cfg, model, BuildTrainingWindows(ds, 2, cfg.multimodal, "", ""),
                                   out.path().string(), {}, {}),
                    Catch::Contains("its windows were built in the data's axes"));
  TrainGenerator(cfg, model, data, out.path().string(), {}, {});

  TrajectoryTrainOptions t;
  t.hidden = 64;
  t.layers = 2;
  t.n_out = 4;
  t.epochs = 30;
  t.lr_constant_epochs = 20;
  t.batch = 32;
  t.window_stride = 1;
  t.learning_rate = 3e-3;
  t.validation_every = 3;
  const std::vector<int> feet = {3, 6};  // Foot_R, Foot_L
  const TrajectoryTrainSummary s = TrainTrajectory(t, model, ds, feet, out.path().string(), {});
  REQUIRE(s.validation_windows > 0);
  // Standing still would end 10 frames x 4 cm = 0.4 m behind.
  INFO("validation root ADE " << s.val_ade << ", FDE " << s.val_fde);
  CHECK(s.val_fde < 0.1);
  CHECK(TrajectoryTrained(out.path().string()));

  const Forecaster f = LoadForecaster(out.path().string());
  REQUIRE(f.moves_root());
  ForecastRequest req;
  req.k = 6;
  req.seed = 5;
  const Motion& clip = ds.clips[1].motion;
  const Forecast a = f.Predict(clip, 20, req);
  CHECK(a.root_moves);
  // The root walks on: every future's last root is at least 0.2 m from the last history root.
  const int J = 17;
  const float* last = a.history.data() + (a.t_his - 1) * J * 3;
  for (int k = 0; k < req.k; ++k) {
    const float* end = a.futures.data() + ((k * a.t_pred) + a.t_pred - 1) * J * 3;
    CHECK(std::hypot(end[0] - last[0], end[2] - last[2]) > 0.2);
  }
  // Turned by 1.1 rad about Y and moved: every future turned and moved alike.
  std::vector<float> moved = clip.positions();
  RotateAboutUp(moved.data(), moved.size() / 3, 1.1, UpAxis{1, 1});
  for (size_t i = 0; i < moved.size(); i += 3) {
    moved[i] += 3.0f;
    moved[i + 1] += 0.2f;
    moved[i + 2] -= 5.0f;
  }
  const Forecast b = f.Predict(Motion(clip.skeleton_ptr(), clip.fps(), moved), 20, req);
  std::vector<float> expect = a.futures;
  RotateAboutUp(expect.data(), expect.size() / 3, 1.1, UpAxis{1, 1});
  double worst = 0;
  for (size_t i = 0; i < expect.size(); i += 3) {
    const float shift[3] = {3.0f, 0.2f, -5.0f};
    for (int ax = 0; ax < 3; ++ax)
      worst = std::max(
          worst, std::abs(static_cast<double>(expect[i + ax] + shift[ax]) - b.futures[i + ax]));
  }
  CHECK(worst < 1e-4);

  // The same legs, the same path: every future's root where the first future's is.
  req.fixed_parts = {"legs"};
  const Forecast c = f.Predict(clip, 20, req);
  for (int k = 1; k < req.k; ++k)
    for (int t = 0; t < c.t_pred; ++t)
      for (int ax = 0; ax < 3; ++ax)
        CHECK(c.futures[((k * c.t_pred) + t) * J * 3 + ax] == c.futures[t * J * 3 + ax]);
}

TEST_CASE("a trajectory needs a generator in the body's frame") {
  testing::TempDir out;
  const Dataset ds = testing::SyntheticDataset(4, 40);
  GeneratorTrainConfig cfg = testing::TinyConfig();
  cfg.training.epochs = 1;
  cfg.training.lr_constant_epochs = 1;
  const ModelConfig model = testing::ModelFor(ds, cfg);
  TrainGenerator(cfg, model, BuildTrainingWindows(ds, 3, cfg.multimodal, "", ""),
                 out.path().string(), {}, {});
  CHECK_THROWS_WITH(TrainTrajectory({}, model, ds, {}, out.path().string(), {}),
                    Catch::Contains("body_frame: true"));
  Forecaster f = LoadForecaster(out.path().string());
  CHECK_FALSE(f.moves_root());
  CHECK_THROWS_WITH(f.AttachTrajectory(RandomNet(SmallOptions()).ptr()),
                    Catch::Contains("trained in the body's frame"));
}

TEST_CASE("in the body's frame a window's pseudo futures do not depend on which way it faced") {
  // The same walks, turned a different way per clip or not at all: matched in the body's frame
  // every window finds the same pseudo futures; in the data's own axes the turned walks find
  // others, whether the generator works in the body's frame or not.
  MultimodalOptions o = testing::TinyConfig().multimodal;
  o.max_per_window = 1000;  // every candidate, so that the sets compare as sets
  auto sets = [&](const Dataset& ds, const std::string& body_frame, bool matched_in_body) {
    o.body_frame = matched_in_body;
    std::vector<std::vector<int32_t>> out =
        BuildTrainingWindows(ds, 2, o, body_frame, "").multimodal;
    for (auto& s : out) std::sort(s.begin(), s.end());
    return out;
  };
  const Dataset plain = testing::SyntheticDataset(8, 60), turned = TurnedWalks(8, 60);
  const auto body_plain = sets(plain, "y", true), body_turned = sets(turned, "y", true);
  size_t pairs = 0;
  for (const auto& s : body_plain) pairs += s.size();
  CHECK(pairs > 0);
  CHECK(body_turned == body_plain);
  CHECK(sets(turned, "", false) != sets(plain, "", false));
  CHECK(sets(turned, "y", false) == sets(turned, "", false));
  CHECK_THROWS_WITH(sets(plain, "", true), Catch::Contains("multimodal.body_frame needs"));
}

TEST_CASE("a pseudo window is gathered turned as it was matched") {
  const Dataset ds = TurnedWalks(8, 60);
  MultimodalOptions o = testing::TinyConfig().multimodal;
  for (const bool in_body : {false, true}) {
    o.body_frame = in_body;
    const TrainingWindows tw = BuildTrainingWindows(ds, 2, o, "y", "");
    REQUIRE(tw.up);
    const size_t n = static_cast<size_t>(tw.num_frames()) * tw.num_nodes * 3;
    std::vector<float> got(n), want(n);
    int checked = 0;
    for (int w = 0; w < static_cast<int>(tw.windows.size()) && checked < 20; ++w) {
      if (tw.multimodal[w].empty()) continue;
      const int v = tw.multimodal[w][0];
      tw.GatherPseudo(w, 0, got.data());
      // Window v as recorded, turned by its own turn or by window w's.
      const Window& win = tw.windows[v];
      const float* src = tw.clip_poses[win.clip].data() + win.start * tw.num_nodes * 3;
      std::copy(src, src + n, want.begin());
      RotateAboutUp(want.data(), n / 3, in_body ? tw.turn[v] : tw.turn[w], *tw.up);
      for (size_t i = 0; i < n; ++i) REQUIRE(got[i] == Approx(want[i]).margin(1e-6));
      ++checked;
    }
    CHECK(checked > 0);
  }
}
