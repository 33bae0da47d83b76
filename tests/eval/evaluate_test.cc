// The evaluation job: figures cross-checked against a direct computation written here, the
// plausibility-scorer hook, the controllable setting and the errors a user can meet.
#include "eval/evaluate.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "eval/baselines.h"
#include "test_support.h"

using namespace motionfork;

namespace {

ProtocolOptions Protocol() {
  ProtocolOptions p;
  p.name = "small";
  p.skeleton = "test_humanoid";
  p.fps = 30;
  p.t_his = 5;
  p.t_pred = 10;
  p.test_stride = 5;
  p.test_include_last = true;
  return p;
}

struct Fixture {
  std::vector<Clip> clips;
  TestSet ts;
  explicit Fixture(double threshold = 0.5) {
    const char* actions[] = {"walk", "wave", "walk", "run"};
    for (int c = 0; c < 4; ++c) {
      Clip clip;
      clip.name = "clip" + std::to_string(c);
      clip.action = actions[c];
      clip.split = Split::kTest;
      clip.motion = testing::MakeWalkingMotion(40 + 7 * c, 30, 100 + c);
      clips.push_back(std::move(clip));
    }
    std::vector<const Clip*> ptrs;
    for (const Clip& c : clips) ptrs.push_back(&c);
    ts = BuildTestSet(ptrs, Protocol());
    AttachMultimodalSets(&ts, threshold, "", "small");
  }
};

// Root-relative pose vector [48] of a [17, 3] frame.
std::vector<double> PoseVector(const float* f) {
  std::vector<double> v;
  for (int j = 1; j < 17; ++j)
    for (int a = 0; a < 3; ++a) v.push_back(double(f[3 * j + a]) - f[a]);
  return v;
}

double Dist(const std::vector<double>& a, const float* b) {
  double d2 = 0;
  for (size_t e = 0; e < a.size(); ++e) d2 += (a[e] - b[e]) * (a[e] - b[e]);
  return std::sqrt(d2);
}

// A stochastic predictor for the hook and seed tests: the last pose plus seeded noise.
class NoisyPredictor : public Predictor {
 public:
  NoisyPredictor(std::shared_ptr<const Skeleton> s, int t_his, int t_pred)
      : s_(std::move(s)), t_his_(t_his), t_pred_(t_pred) {}
  std::string name() const override { return "noisy"; }
  const Skeleton& skeleton() const override { return *s_; }
  int t_his() const override { return t_his_; }
  int t_pred() const override { return t_pred_; }
  uint64_t poison_seed = 0;  // a NaN in the output of the call with this seed

 protected:
  void DoPredict(const float* history, const PredictRequest& r, float* futures) override {
    std::mt19937_64 rng(r.seed);
    std::normal_distribution<float> n(0, 0.05f);
    const float* last = history + (t_his_ - 1) * 51;
    for (int f = 0; f < r.num_samples * t_pred_; ++f) {
      for (int e = 0; e < 51; ++e) futures[f * 51 + e] = last[e] + n(rng);
    }
    if (poison_seed != 0 && r.seed == poison_seed)
      futures[7] = std::numeric_limits<float>::quiet_NaN();
  }

 private:
  std::shared_ptr<const Skeleton> s_;
  int t_his_, t_pred_;
};

}  // namespace

TEST_CASE("zero-velocity figures equal a direct computation of the protocol's definitions") {
  Fixture fx(0.3);
  const TestSet& ts = fx.ts;
  // 40, 47, 54, 61 frames, windows of 15, stride 5: starts 0..25, 0..30, 0..35, 0..45.
  REQUIRE(ts.num_windows() == 6 + 7 + 8 + 10);
  ZeroVelocityPredictor zv(ts.skeleton, ts.t_his, ts.t_pred);
  EvalOptions o;
  o.num_samples = 4;
  const EvalResult r = Evaluate(zv, ts, o);

  // Direct: every sample is the last history pose p_i. Window j is in i's set when their last
  // poses are closer than 0.3 m.
  const int N = ts.num_windows(), T = ts.t_pred;
  std::vector<std::vector<double>> last(N);
  for (int i = 0; i < N; ++i) last[i] = PoseVector(ts.history(i) + (ts.t_his - 1) * 51);
  double ade = 0, fde = 0, mmade = 0, mmfde = 0, set_size = 0;
  int non_singleton = 0;
  for (int i = 0; i < N; ++i) {
    auto displacement = [&](int j, double* a, double* f) {
      *a = 0;
      for (int t = 0; t < T; ++t) *a += Dist(last[i], ts.future(j) + t * 48) / T;
      *f = Dist(last[i], ts.future(j) + (T - 1) * 48);
    };
    double a, f;
    displacement(i, &a, &f);
    ade += a / N;
    fde += f / N;
    double ma = 0, mf = 0;
    int members = 0;
    for (int j = 0; j < N; ++j) {
      double d2 = 0;
      for (int e = 0; e < 48; ++e) d2 += (last[i][e] - last[j][e]) * (last[i][e] - last[j][e]);
      if (std::sqrt(d2) >= 0.3) continue;
      displacement(j, &a, &f);
      ma += a;
      mf += f;
      ++members;
    }
    mmade += ma / members / N;
    mmfde += mf / members / N;
    set_size += double(members) / N;
    non_singleton += members > 1;
  }
  REQUIRE(non_singleton > 0);  // the threshold makes some sets non-trivial
  CHECK(r.overall.windows == N);
  CHECK(r.overall.apd == 0.0);
  CHECK(r.overall.ade == Approx(ade).epsilon(1e-5));
  CHECK(r.overall.fde == Approx(fde).epsilon(1e-5));
  CHECK(r.overall.mmade == Approx(mmade).epsilon(1e-5));
  CHECK(r.overall.mmfde == Approx(mmfde).epsilon(1e-5));
  CHECK(r.overall.mean_set_size == Approx(set_size));

  // Per action: walk = clips 0 and 2, run = clip 3, wave = clip 1; window-weighted means add up.
  REQUIRE(ts.actions == std::vector<std::string>{"run", "walk", "wave"});
  CHECK(r.per_action[0].windows == 10);
  CHECK(r.per_action[1].windows == 6 + 8);
  CHECK(r.per_action[2].windows == 7);
  double weighted = 0;
  for (const Figures& f : r.per_action) weighted += f.ade * f.windows / N;
  CHECK(weighted == Approx(r.overall.ade).epsilon(1e-9));
  CHECK(r.seconds_metrics > 0);
}

TEST_CASE("GSPS's rule leaves singleton windows out of every figure") {
  // A threshold between the windows' nearest-other distances makes about half of them singletons.
  Fixture fx;
  const int N = fx.ts.num_windows();
  std::vector<std::vector<double>> last(N);
  for (int i = 0; i < N; ++i) last[i] = PoseVector(fx.ts.history(i) + (fx.ts.t_his - 1) * 51);
  std::vector<double> nearest(N, 1e9);
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) {
      if (j == i) continue;
      double d2 = 0;
      for (int e = 0; e < 48; ++e) d2 += (last[i][e] - last[j][e]) * (last[i][e] - last[j][e]);
      nearest[i] = std::min(nearest[i], std::sqrt(d2));
    }
  }
  std::sort(nearest.begin(), nearest.end());
  AttachMultimodalSets(&fx.ts, 0.5 * (nearest[N / 2 - 1] + nearest[N / 2]), "", "small");
  ZeroVelocityPredictor zv(fx.ts.skeleton, fx.ts.t_his, fx.ts.t_pred);
  EvalOptions o;
  o.num_samples = 2;
  const EvalResult all = Evaluate(zv, fx.ts, o);
  o.keep_singleton_sets = false;
  const EvalResult gsps = Evaluate(zv, fx.ts, o);
  int singletons = 0;
  double ade = 0;
  for (int i = 0; i < fx.ts.num_windows(); ++i) {
    if (fx.ts.multimodal.set_size(i) == 1) {
      ++singletons;
      CHECK(!gsps.evaluated[i]);
    } else {
      ade += all.per_window[i].ade;
    }
  }
  REQUIRE(singletons > 0);
  CHECK(gsps.windows_skipped == singletons);
  CHECK(gsps.overall.windows == fx.ts.num_windows() - singletons);
  CHECK(gsps.overall.ade == Approx(ade / gsps.overall.windows));
  // A threshold so small that every set is a singleton: nothing left to evaluate.
  Fixture tiny(1e-9);
  CHECK_THROWS_WITH(Evaluate(zv, tiny.ts, o), Catch::Contains("singleton"));
}

TEST_CASE("seeds: per window, reproducible, independent of other windows") {
  Fixture fx;
  NoisyPredictor p(fx.ts.skeleton, fx.ts.t_his, fx.ts.t_pred);
  EvalOptions o;
  o.num_samples = 5;
  o.seed = 7;
  const EvalResult a = Evaluate(p, fx.ts, o);
  const EvalResult b = Evaluate(p, fx.ts, o);
  CHECK(a.overall.apd == b.overall.apd);
  CHECK(a.overall.ade == b.overall.ade);
  CHECK(a.overall.apd > 0);
  o.seed = 8;
  CHECK(Evaluate(p, fx.ts, o).overall.apd != a.overall.apd);
  CHECK(WindowSeed(7, 0) != WindowSeed(7, 1));
  CHECK(WindowSeed(7, 3) == WindowSeed(7, 3));
  // A non-finite prediction names the window.
  p.poison_seed = WindowSeed(7, 4);
  o.seed = 7;
  CHECK_THROWS_WITH(Evaluate(p, fx.ts, o),
                    Catch::Contains("non-finite") && Catch::Contains("window 4"));
}

TEST_CASE("frame scorers: plausibility figures of predicted and ground-truth frames") {
  Fixture fx;
  const TestSet& ts = fx.ts;
  ZeroVelocityPredictor zv(ts.skeleton, ts.t_his, ts.t_pred);
  // Scorer: height of the head above the root (root-relative Y of joint 10), one per frame.
  FrameScorer head{"head_height", [](const float* p, int n, double* out) {
                     for (int f = 0; f < n; ++f) {
                       CHECK(p[f * 51 + 0] == 0.0f);  // root at the origin
                       out[f] = p[f * 51 + 30 + 1];
                     }
                   }};
  EvalOptions o;
  o.num_samples = 3;
  o.scorers = {head};
  const EvalResult r = Evaluate(zv, ts, o);
  double pred = 0, truth = 0;
  const int N = ts.num_windows();
  for (int i = 0; i < N; ++i) {
    const float* last = ts.history(i) + (ts.t_his - 1) * 51;
    pred += (double(last[31]) - last[1]) / N;
    for (int t = 0; t < ts.t_pred; ++t)
      truth += ts.future(i)[t * 48 + 9 * 3 + 1] / (double(N) * ts.t_pred);
  }
  REQUIRE(r.overall.predicted_scores.size() == 1);
  CHECK(r.overall.predicted_scores[0] == Approx(pred).epsilon(1e-6));
  CHECK(r.overall.truth_scores[0] == Approx(truth).epsilon(1e-6));
  CHECK(r.per_action[0].predicted_scores.size() == 1);

  FrameScorer bad{"bad", [](const float*, int n, double* out) {
                    for (int f = 0; f < n; ++f) out[f] = std::nan("");
                  }};
  o.scorers = {bad};
  CHECK_THROWS_WITH(Evaluate(zv, ts, o), Catch::Contains("scorer 'bad'"));
  o.scorers = {FrameScorer{"empty", {}}};
  CHECK_THROWS_WITH(Evaluate(zv, ts, o), Catch::Contains("no function"));
}

TEST_CASE("the controllable setting: APD of the varied part, spread of the fixed one") {
  Fixture fx;
  const TestSet& ts = fx.ts;
  std::vector<const Motion*> training;
  for (const Clip& c : fx.clips) training.push_back(&c.motion);
  NearestNeighbourPredictor nn(training, ts.t_his, ts.t_pred);
  EvalOptions o;
  o.num_samples = 6;
  o.fixed_part = 0;  // legs
  const EvalResult r = Evaluate(nn, ts, o);
  CHECK(r.fixed_part == "legs");
  CHECK(r.overall.apd_fixed == Approx(0.0).margin(1e-5));
  CHECK(r.overall.apd_varied > 0.01);
  CHECK(r.overall.apd > r.overall.apd_varied * 0.99);  // the fixed part adds nothing
  // A predictor that cannot fix a part says so.
  NoisyPredictor noisy(ts.skeleton, ts.t_his, ts.t_pred);
  CHECK_THROWS_WITH(Evaluate(noisy, ts, o), Catch::Contains("cannot fix a body part"));
  o.fixed_part = 5;
  CHECK_THROWS_WITH(Evaluate(nn, ts, o), Catch::Contains("got 5"));
}

TEST_CASE("bad input: K < 2, another skeleton, other lengths, missing multimodal sets") {
  Fixture fx;
  const TestSet& ts = fx.ts;
  ZeroVelocityPredictor zv(ts.skeleton, ts.t_his, ts.t_pred);
  EvalOptions o;
  o.num_samples = 1;
  CHECK_THROWS_WITH(Evaluate(zv, ts, o),
                    Catch::Contains("expected K >= 2") && Catch::Contains("got 1"));
  o.num_samples = 2;
  auto other = std::make_shared<const Skeleton>(Skeleton::Anonymous(15));
  ZeroVelocityPredictor wrong(other, ts.t_his, ts.t_pred);
  CHECK_THROWS_WITH(Evaluate(wrong, ts, o), Catch::Contains("skeleton") &&
                                                Catch::Contains("15 joints") &&
                                                Catch::Contains("17 joints"));
  ZeroVelocityPredictor longer(ts.skeleton, ts.t_his, ts.t_pred + 1);
  CHECK_THROWS_WITH(Evaluate(longer, ts, o), Catch::Contains("predicts 11 frames from 5"));
  TestSet bare = ts;
  bare.multimodal = MultimodalSets();
  CHECK_THROWS_WITH(Evaluate(zv, bare, o), Catch::Contains("AttachMultimodalSets"));
}

TEST_CASE("root figures: the world root and feet against a direct computation, same threads") {
  const Fixture fx;
  const TestSet& ts = fx.ts;
  const int N = ts.num_windows(), T = ts.t_pred, J = 17, K = 3;
  const std::vector<int> feet = {3, 6};  // the humanoid's ankles (H36M order)
  ZeroVelocityPredictor zv(ts.skeleton, ts.t_his, T);
  EvalOptions o;
  o.num_samples = K;
  o.root.enabled = true;
  o.root.up = {1, 1};
  o.root.feet = feet;
  const EvalResult r = Evaluate(zv, ts, o);
  // Directly from the clips: every sample keeps the last history root and pose.
  double ade = 0, fde = 0, truth_skating = 0;
  double moved = 0;
  for (int i = 0; i < N; ++i) {
    const Window& w = ts.windows[i];
    const Motion& m = fx.clips[w.clip].motion;
    const float* last = m.frame(w.start + ts.t_his - 1);
    double sum = 0, d = 0;
    for (int t = 0; t < T; ++t) {
      const float* f = m.frame(w.start + ts.t_his + t);
      d = std::sqrt(std::pow(f[0] - last[0], 2.0) + std::pow(f[1] - last[1], 2.0) +
                    std::pow(f[2] - last[2], 2.0));
      sum += d;
    }
    ade += sum / T;
    fde += d;
    moved += d;
    const double ground = GroundHeight(m.frame(w.start), ts.t_his, J, feet, o.root.up);
    truth_skating += FootSkating(m.frame(w.start + ts.t_his), T, J, feet, o.root.up, ground, 0.05);
  }
  REQUIRE(moved / N > 0.1);  // the fixture's bodies walk: a root that stays is wrong
  CHECK(r.overall.root.ade == Approx(ade / N).epsilon(1e-6));
  CHECK(r.overall.root.fde == Approx(fde / N).epsilon(1e-6));
  CHECK(r.overall.root.final_spread == 0.0);
  CHECK(r.overall.root.skating == 0.0);  // the feet stand still
  CHECK(r.overall.root.truth_skating == Approx(truth_skating / N).epsilon(1e-5));
  // The root-relative figures do not change with the root's on.
  o.root.enabled = false;
  const EvalResult plain = Evaluate(zv, ts, o);
  CHECK(plain.overall.ade == r.overall.ade);
  CHECK(plain.overall.fde == r.overall.fde);
  CHECK(plain.overall.root.ade == 0.0);
  // Threads do not change them.
  o.root.enabled = true;
  o.threads = 2;
  const EvalResult two = Evaluate(zv, ts, o);
  CHECK(two.overall.root.ade == r.overall.root.ade);
  CHECK(two.overall.root.truth_skating == r.overall.root.truth_skating);
  // A test set without root futures is refused when the root figures are asked for.
  TestSet bare = ts;
  bare.root_futures.clear();
  CHECK_THROWS_WITH(Evaluate(zv, bare, o), Catch::Contains("root futures"));
}
