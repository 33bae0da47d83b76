// Training augmentation (generator/training/augmentation.h): draws, mirroring, size, speed and
// history noise, and a tiny training run that uses them all.
#include "generator/training/augmentation.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/heading.h"
#include "generator/training/training.h"
#include "generator/training/training_data.h"
#include "synthetic_training.h"
#include "test_support.h"
#include "torch_catch.h"

using namespace motionfork;
using testing::ModelFor;
using testing::SyntheticDataset;
using testing::TinyConfig;

namespace {

// Windows over hand-made clips: node n of frame f at (f + n, 10 n, -n) so that frames are easy
// to tell apart and to interpolate. N nodes, t_his 3, t_pred 4.
TrainingWindows LinearWindows(int nodes, int frames) {
  TrainingWindows tw;
  tw.t_his = 3;
  tw.t_pred = 4;
  tw.num_nodes = nodes;
  std::vector<float> clip;
  for (int f = 0; f < frames; ++f)
    for (int n = 0; n < nodes; ++n) clip.insert(clip.end(), {float(f + n), 10.0f * n, -1.0f * n});
  tw.clip_poses = {clip};
  for (int s = 0; s + tw.num_frames() <= frames; ++s) tw.windows.push_back({0, s});
  tw.multimodal.resize(tw.windows.size());
  return tw;
}

double BoneLength(const std::vector<float>& pose, const Skeleton& sk, int node) {
  const int p = sk.parent(node + 1) - 1;
  double s = 0;
  for (int k = 0; k < 3; ++k)
    s += std::pow(pose[3 * node + k] - (p < 0 ? 0.0f : pose[3 * p + k]), 2);
  return std::sqrt(s);
}

std::string ReadAll(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST_CASE("augmentation draws: none when off, within their ranges and symmetric when on") {
  std::mt19937_64 rng(3), untouched(3);
  const std::vector<WindowAugmentation> off = DrawAugmentations(AugmentationOptions{}, 50, rng);
  REQUIRE(off.size() == 50u);
  for (const WindowAugmentation& a : off) CHECK((!a.mirror && a.scale == 1 && a.speed == 1));
  CHECK(rng() == untouched());  // nothing drawn: a run without augmentation draws as before

  AugmentationOptions o;
  o.mirror = 0.3;
  o.scale = 1.1;
  o.speed = 1.5;
  const std::vector<WindowAugmentation> on = DrawAugmentations(o, 20000, rng);
  double mirrored = 0, log_scale = 0, log_speed = 0;
  for (const WindowAugmentation& a : on) {
    CHECK(a.scale >= 1 / 1.1 - 1e-12);
    CHECK(a.scale <= 1.1 + 1e-12);
    CHECK(a.speed >= 1 / 1.5 - 1e-12);
    CHECK(a.speed <= 1.5 + 1e-12);
    mirrored += a.mirror;
    log_scale += std::log(a.scale);
    log_speed += std::log(a.speed);
  }
  CHECK(mirrored / on.size() == Approx(0.3).margin(0.02));
  CHECK(log_scale / on.size() == Approx(0).margin(0.003));  // log-uniform about 1
  CHECK(log_speed / on.size() == Approx(0).margin(0.01));
  // The same seed, the same draws.
  std::mt19937_64 a(9), b(9);
  const auto da = DrawAugmentations(o, 10, a), db = DrawAugmentations(o, 10, b);
  for (size_t i = 0; i < da.size(); ++i) {
    CHECK(da[i].mirror == db[i].mirror);
    CHECK(da[i].speed == db[i].speed);
  }
}

TEST_CASE("mirroring exchanges left and right, reflects the hip line's axis and keeps bones") {
  const Dataset ds = SyntheticDataset(8, 60);
  const GeneratorTrainConfig cfg = TinyConfig();
  testing::TempDir cache;
  const TrainingWindows data = BuildTrainingWindows(ds, cfg.training.window_stride, cfg.multimodal,
                                                    "", cache.path().string());
  const Skeleton& sk = *ds.skeleton.skeleton;
  const MirrorPlan plan = MakeMirrorPlan(sk, data);
  const HeadingJoints hip = HeadingNodes(sk);
  // The axis chosen is the one the hips lie along in the data (the synthetic walker's: measured).
  std::vector<float> window(static_cast<size_t>(data.num_frames()) * data.num_nodes * 3);
  data.Gather(0, window.data());
  const float* last = window.data() + static_cast<size_t>(data.t_his - 1) * data.num_nodes * 3;
  int widest = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(last[3 * hip.left + k] - last[3 * hip.right + k]) >
        std::abs(last[3 * hip.left + widest] - last[3 * hip.right + widest]))
      widest = k;
  }
  CHECK(plan.axis == widest);
  CHECK(plan.partner[hip.left] == hip.right);
  CHECK(plan.partner[hip.right] == hip.left);
  const int spine = sk.Index("Spine") - 1;
  CHECK(plan.partner[spine] == spine);

  std::vector<float> m = window;
  MirrorPoses(plan, data.num_frames(), m.data());
  CHECK(m != window);
  // The left hip now sits where the right one was, with its lateral coordinate negated.
  for (int k = 0; k < 3; ++k) {
    const float want = window[3 * hip.right + k] * (k == plan.axis ? -1.0f : 1.0f);
    CHECK(m[3 * hip.left + k] == want);
  }
  for (int n = 0; n < data.num_nodes; ++n)  // bones keep their lengths (as their partners')
    CHECK(BoneLength(m, sk, n) == Approx(BoneLength(window, sk, plan.partner[n])).epsilon(1e-5));
  MirrorPoses(plan, data.num_frames(), m.data());
  CHECK(m == window);  // twice: the original

  std::vector<float> s = window;
  ScalePoses(1.1, s.size(), s.data());
  for (int n = 0; n < data.num_nodes; ++n)
    CHECK(BoneLength(s, sk, n) == Approx(1.1 * BoneLength(window, sk, n)).epsilon(1e-5));
}

TEST_CASE("in the body's frame a mirrored window keeps its heading at the last history frame") {
  const Dataset ds = SyntheticDataset(8, 60);
  const GeneratorTrainConfig cfg = TinyConfig();
  const TrainingWindows data =
      BuildTrainingWindows(ds, cfg.training.window_stride, cfg.multimodal, "y", "");
  const Skeleton& sk = *ds.skeleton.skeleton;
  const MirrorPlan plan = MakeMirrorPlan(sk, data);
  CHECK(plan.axis == GroundAxes(*data.up).first);  // the body frame puts the hips along it
  const HeadingJoints hip = HeadingNodes(sk);
  const int N = data.num_nodes;
  std::vector<float> window(static_cast<size_t>(data.num_frames()) * N * 3);
  for (int w : {0, 17, 60}) {
    data.Gather(w, window.data());
    const float* last = window.data() + static_cast<size_t>(data.t_his - 1) * N * 3;
    const double before = HeadingAngle(last, hip, *data.up);
    MirrorPoses(plan, data.num_frames(), window.data());
    const double after = HeadingAngle(last, hip, *data.up);
    INFO("window " << w << ": heading " << before << " -> " << after);
    CHECK(std::abs(before) < 1e-4);
    CHECK(std::abs(after) < 1e-4);
    // Another axis turns it round: a mirror that kept nothing would fail here.
    MirrorPlan wrong = plan;
    wrong.axis = GroundAxes(*data.up).second;
    MirrorPoses(plan, data.num_frames(), window.data());  // back
    MirrorPoses(wrong, data.num_frames(), window.data());
    CHECK(std::abs(std::abs(HeadingAngle(last, hip, *data.up)) - M_PI) < 1e-4);
  }
}

TEST_CASE("a window and its pseudo futures are read at one speed, the one that fits them all") {
  TrainingWindows tw = LinearWindows(2, 40);
  const int T = tw.num_frames(), N = 2;
  tw.multimodal[10] = {30, 5};  // window 30 fits 1.75 at most (its future), window 5 3.5 (history)
  CHECK(tw.SharedSpeed(10, 1, 2.0) == Approx(1.75));
  CHECK(tw.SharedSpeed(10, 2, 2.0) == Approx(1.75));
  CHECK(tw.SharedSpeed(10, 0, 2.0) == 2.0);  // no pseudo windows used: the window's own
  CHECK(tw.SharedSpeed(10, 2, 0.8) == 0.8);
  std::vector<float> out(static_cast<size_t>(T) * N * 3);
  tw.GatherPseudo(10, 0, out.data(), 1.75);
  for (int t = 0; t < T; ++t)  // window 30's last history frame is 32
    CHECK(out[(t * N) * 3] == Approx(32 + 1.75 * (t - 2)));
}

TEST_CASE("a window read faster or slower keeps its last history frame and interpolates") {
  const TrainingWindows tw = LinearWindows(2, 40);
  const int T = tw.num_frames(), N = 2;
  std::vector<float> plain(static_cast<size_t>(T) * N * 3), out = plain;
  const int w = 10;  // start 10: last history frame 12, future to 16
  tw.Gather(w, plain.data());
  tw.Gather(w, out.data(), 1.0);
  CHECK(out == plain);
  for (double speed : {0.5, 0.75, 1.5, 2.0}) {
    INFO("speed " << speed);
    tw.Gather(w, out.data(), speed);
    for (int t = 0; t < T; ++t) {
      const double frame = 12 + speed * (t - 2);
      CHECK(out[(t * N + 1) * 3] == Approx(frame + 1));  // node 1's x is frame + 1
      CHECK(out[(t * N + 1) * 3 + 1] == 10.0f);          // the rest as recorded
    }
  }
  // Near a clip's end the factor drops to the largest that fits: window 33 (frames 33..39,
  // last history frame 35) has 4 frames of future, so at most 1.0; window 30 has 7: 1.75.
  CHECK(tw.SpeedThatFits(33, 2.0) == 1.0);
  CHECK(tw.SpeedThatFits(30, 2.0) == Approx(1.75));
  CHECK(tw.SpeedThatFits(30, 0.5) == 0.5);
  tw.Gather(30, out.data(), 2.0);
  CHECK(out[((T - 1) * N) * 3] == Approx(39.0));  // the clip's last frame, not past it
  // Near its start too: window 0's last history frame is 2, two frames from the start: 1.0.
  CHECK(tw.SpeedThatFits(0, 3.0) == 1.0);
}

TEST_CASE("history noise has the asked spread and none when off") {
  std::mt19937_64 rng(1);
  std::vector<float> v(40000, 0.0f);
  AddNoise(0, v.size(), rng, v.data());
  CHECK(v == std::vector<float>(40000, 0.0f));
  AddNoise(0.02, v.size(), rng, v.data());
  double s = 0, s2 = 0;
  for (float x : v) {
    s += x;
    s2 += double(x) * x;
  }
  CHECK(s / v.size() == Approx(0).margin(5e-4));
  CHECK(std::sqrt(s2 / v.size()) == Approx(0.02).epsilon(0.02));
}

TEST_CASE(
    "training with every augmentation runs, repeats itself and differs from training without") {
  const Dataset ds = SyntheticDataset(8, 60);
  GeneratorTrainConfig plain = TinyConfig();
  plain.training.epochs = plain.training.lr_constant_epochs = 2;
  GeneratorTrainConfig varied = plain;
  varied.augmentation.mirror = 0.5;
  varied.augmentation.scale = 1.1;
  varied.augmentation.speed = 1.3;
  varied.augmentation.history_noise = 0.01;
  testing::TempDir cache, a, b, c;
  const TrainingWindows data = BuildTrainingWindows(ds, plain.training.window_stride,
                                                    plain.multimodal, "", cache.path().string());
  std::vector<std::string> messages;
  TrainCallbacks cb;
  cb.message = [&](const std::string& m) { messages.push_back(m); };
  TrainGenerator(varied, ModelFor(ds, varied), data, a.path().string(), {}, cb);
  TrainGenerator(varied, ModelFor(ds, varied), data, b.path().string(), {}, {});
  TrainGenerator(plain, ModelFor(ds, plain), data, c.path().string(), {}, {});
  const std::string wa = ReadAll(a.path() / "generator.pt"),
                    wb = ReadAll(b.path() / "generator.pt"),
                    wc = ReadAll(c.path() / "generator.pt");
  REQUIRE_FALSE(wa.empty());
  CHECK(wa == wb);  // same seed, same varied windows, same weights
  CHECK(wa != wc);
  bool told = false;
  for (const std::string& m : messages) told = told || m.find("mirroring") != std::string::npos;
  CHECK(told);
}
