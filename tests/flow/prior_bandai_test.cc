// The pose prior on real motion capture (Bandai test split = the unseen 'elderly' style): real
// poses score better than the same poses with noisy limb directions and than impossible poses
// built from them by rotating limb directions. Reports the AUROC of the NLL separating real from
// impossible poses (target >= 0.95), for a prior trained here in seconds and for the shipped one.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>

#include "bundle/prior_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "flow/catch_torch.h"
#include "flow/pose_prior.h"
#include "flow/prior_data.h"
#include "flow/trainer.h"
#include "test_support.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

struct Bandai {
  Dataset dataset;
  std::shared_ptr<const Skeleton> skeleton;
};

// Loaded once per process (first run parses the archives, ~7 s; later runs read the cache kept in
// the build folder).
const Bandai* LoadBandai() {
  static std::unique_ptr<Bandai> cached;
  if (cached) return cached.get();
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) return nullptr;
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", "bandai"));
  const SkeletonConfig s =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", p.skeleton));
  DatasetLoadOptions opts;
  opts.cache_dir = std::string(MOTIONFORK_BINARY_DIR) + "/test_cache";
  cached = std::make_unique<Bandai>();
  cached->dataset = LoadDataset(p, s, data, opts);
  cached->skeleton = s.skeleton;
  return cached.get();
}

using Vec = std::array<double, 3>;
Vec Sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec Scale(const Vec& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Vec Add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
double Dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec Cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec Unit(const Vec& a) { return Scale(a, 1.0 / std::sqrt(Dot(a, a))); }
// The component of a orthogonal to the unit vector n, normalised.
Vec Orthogonal(const Vec& a, const Vec& n) { return Unit(Sub(a, Scale(n, Dot(a, n)))); }
// Unit vector at `degrees` from unit a towards the direction b (orthogonalised against a).
Vec Towards(const Vec& a, const Vec& b, double degrees) {
  const double r = degrees * M_PI / 180;
  return Add(Scale(a, std::cos(r)), Scale(Orthogonal(b, a), std::sin(r)));
}

// One pose's limb directions with named access (limb of joint j = j - 1).
class Pose {
 public:
  Pose(const Skeleton& s, const float* d) : s_(s), d_(d, d + 3 * (s.num_joints() - 1)) {}
  Vec Get(const char* joint) const {
    const int k = s_.Index(joint) - 1;
    return {d_[3 * k], d_[3 * k + 1], d_[3 * k + 2]};
  }
  void Set(const char* joint, const Vec& v) {
    const int k = s_.Index(joint) - 1;
    for (int a = 0; a < 3; ++a) d_[3 * k + a] = static_cast<float>(v[a]);
  }
  // Body frame from the pelvis and spine: up (pelvis -> spine), right (left hip -> right hip,
  // orthogonal to up), forward = up x right (right-handed coordinates, as BVH and the fixtures).
  Vec Up() const { return Unit(Get("Spine")); }
  Vec Right() const { return Orthogonal(Sub(Get("UpperLeg_R"), Get("UpperLeg_L")), Up()); }
  Vec Forward() const { return Cross(Up(), Right()); }
  const std::vector<float>& directions() const { return d_; }

 private:
  const Skeleton& s_;
  std::vector<float> d_;
};

const char* const kImpossibleKinds[] = {"knee bent backwards 60 deg", "head rotated 180 deg",
                                        "arm through the torso", "legs split 200 deg"};

// Impossible variants of a pose, built by rotating limb directions.
std::vector<float> MakeImpossible(const Skeleton& s, const float* real, int kind) {
  Pose p(s, real);
  const Vec up = p.Up(), right = p.Right(), forward = p.Forward();
  switch (kind) {
    case 0: {  // right shin 60 degrees in front of the thigh's line: the knee hyper-extended
      const Vec thigh = p.Get("LowerLeg_R");
      p.Set("Foot_R", Towards(thigh, forward, 60));
      break;
    }
    case 1: {  // neck -> head rotated 180 degrees about the left-right axis: head down, in the
               // chest
      const Vec h = p.Get("Head");
      p.Set("Head", Sub(Scale(right, 2 * Dot(h, right)), h));
      break;
    }
    case 2: {  // left arm straight across the body, slightly backwards: through the chest
      const Vec across = Unit(Sub(right, Scale(forward, 0.2)));
      p.Set("LowerArm_L", across);
      p.Set("Hand_L", across);
      break;
    }
    default: {  // both legs 100 degrees out from straight down: 200 degrees between them
      const Vec down = Scale(up, -1);
      const Vec left_leg = Towards(down, Scale(right, -1), 100),
                right_leg = Towards(down, right, 100);
      p.Set("LowerLeg_L", left_leg);
      p.Set("Foot_L", left_leg);
      p.Set("LowerLeg_R", right_leg);
      p.Set("Foot_R", right_leg);
    }
  }
  return p.directions();
}

// Every limb direction + N(0, sigma^2) per component, re-normalised.
std::vector<float> Perturb(const std::vector<float>& d, double sigma, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<float> out(d.size());
  for (size_t k = 0; k < d.size(); k += 3) {
    Vec v = {d[k] + noise(rng), d[k + 1] + noise(rng), d[k + 2] + noise(rng)};
    v = Unit(v);
    for (int a = 0; a < 3; ++a) out[k + a] = static_cast<float>(v[a]);
  }
  return out;
}

// Probability that a random `other` pose has a higher NLL than a random real pose (ties count
// half): the area under the ROC curve of NLL as a real-vs-other classifier.
double Auroc(std::vector<double> real_nll, const std::vector<double>& other_nll) {
  std::sort(real_nll.begin(), real_nll.end());
  double wins = 0;
  for (double o : other_nll) {
    const auto lo = std::lower_bound(real_nll.begin(), real_nll.end(), o);
    const auto hi = std::upper_bound(real_nll.begin(), real_nll.end(), o);
    wins += (lo - real_nll.begin()) + 0.5 * (hi - lo);
  }
  return wins / (static_cast<double>(real_nll.size()) * other_nll.size());
}

std::vector<double> Nll(const PosePrior& prior, const std::vector<float>& d) {
  std::vector<double> lp = prior.LogProbDirections(d);
  for (double& v : lp) v = -v;
  return lp;
}

double Mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / v.size();
}

struct Separation {
  double real_nll = 0, perturbed_nll = 0;
  double auroc_perturbed = 0, auroc_impossible = 0;
  double auroc_slightly_perturbed = 0;  // sigma 0.05 (about 3 degrees per limb)
  double real_beats_own_perturbed = 0;  // share of poses scoring better than their noisy copy
  double auroc_kind[4] = {0, 0, 0, 0};
  double impossible_nll[4] = {0, 0, 0, 0};
  int poses = 0;
};

// Real test-split poses (every `stride`-th frame) vs perturbed and impossible copies.
Separation Separate(const PosePrior& prior, const PriorFrames& test, const Skeleton& s,
                    int stride) {
  std::vector<float> real;
  for (int64_t i = 0; i < test.size(); i += stride) {
    real.insert(real.end(), test.directions.begin() + i * test.dim,
                test.directions.begin() + (i + 1) * test.dim);
  }
  Separation r;
  r.poses = static_cast<int>(real.size() / test.dim);
  const std::vector<double> real_nll = Nll(prior, real);
  const std::vector<double> pert_nll = Nll(prior, Perturb(real, 0.25, 5));
  r.real_nll = Mean(real_nll);
  r.perturbed_nll = Mean(pert_nll);
  r.auroc_perturbed = Auroc(real_nll, pert_nll);
  r.auroc_slightly_perturbed = Auroc(real_nll, Nll(prior, Perturb(real, 0.05, 6)));
  int better = 0;
  for (int i = 0; i < r.poses; ++i) better += real_nll[i] < pert_nll[i];
  r.real_beats_own_perturbed = static_cast<double>(better) / r.poses;
  std::vector<double> all_impossible;
  for (int kind = 0; kind < 4; ++kind) {
    std::vector<float> imp;
    for (int i = 0; i < r.poses; ++i) {
      const std::vector<float> one =
          MakeImpossible(s, real.data() + static_cast<size_t>(i) * test.dim, kind);
      imp.insert(imp.end(), one.begin(), one.end());
    }
    const std::vector<double> nll = Nll(prior, imp);
    r.auroc_kind[kind] = Auroc(real_nll, nll);
    r.impossible_nll[kind] = Mean(nll);
    all_impossible.insert(all_impossible.end(), nll.begin(), nll.end());
  }
  r.auroc_impossible = Auroc(real_nll, all_impossible);
  return r;
}

std::string Report(const Separation& r) {
  std::string s = std::to_string(r.poses) + " real test poses: mean NLL " +
                  std::to_string(r.real_nll) +
                  "; perturbed (sigma 0.25): " + std::to_string(r.perturbed_nll) + ", AUROC " +
                  std::to_string(r.auroc_perturbed) + ", real beats its own noisy copy in " +
                  std::to_string(100 * r.real_beats_own_perturbed) + "%; sigma 0.05: AUROC " +
                  std::to_string(r.auroc_slightly_perturbed) + "; impossible AUROC " +
                  std::to_string(r.auroc_impossible) + " (";
  for (int k = 0; k < 4; ++k) {
    s += std::string(k ? "; " : "") + kImpossibleKinds[k] + ": NLL " +
         std::to_string(r.impossible_nll[k]) + ", AUROC " + std::to_string(r.auroc_kind[k]);
  }
  return s + ")";
}

}  // namespace

TEST_CASE("bandai: the body frame of the impossible poses is right (real knees bend backwards)") {
  const Bandai* b = LoadBandai();
  if (!b) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  PriorTrainOptions o;
  o.frame_stride = 10;
  const PriorData data = MakePriorData(b->dataset, o);
  // Among test frames whose right knee bends more than 20 degrees, the shin leans backwards
  // (ankle behind the thigh's line) in nearly all: so 'forward' points where the body faces.
  int bent = 0, backwards = 0;
  for (int64_t i = 0; i < data.test.size(); ++i) {
    const Pose p(*b->skeleton, data.test.directions.data() + i * data.test.dim);
    const Vec thigh = p.Get("LowerLeg_R"), shin = p.Get("Foot_R");
    if (Dot(thigh, shin) > std::cos(20 * M_PI / 180)) continue;
    ++bent;
    backwards += Dot(Sub(shin, thigh), p.Forward()) < 0;
  }
  WARN("right knee bent > 20 deg in " << bent << " of " << data.test.size()
                                      << " test frames; shin behind the thigh in " << backwards);
  REQUIRE(bent > 100);
  CHECK(backwards > 0.95 * bent);
}

TEST_CASE(
    "bandai: a prior trained here on train frames scores real poses above noisy and impossible "
    "ones") {
  const Bandai* b = LoadBandai();
  if (!b) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  PinThreads(1);
  PriorConfig config;  // GSPS's settings on every 4th frame, 8 epochs: a few seconds
  config.training.frame_stride = 4;
  config.training.epochs = 8;
  config.training.constant_epochs = 3;
  const PriorData data = MakePriorData(b->dataset, config.training);
  PosePrior prior(b->skeleton, config);
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(TrainPosePrior(prior, data, "").completed);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const PriorTrainingSummary& y = prior.summary();
  const Separation r = Separate(prior, data.test, *b->skeleton, 5);
  WARN("trained in " << seconds << " s on " << data.train.size() << " frames (" << data.train_clips
                     << " clips); held-out NLL " << y.held_out_nll.front() << " -> "
                     << y.held_out_nll.back() << ", test NLL " << y.test_nll << "; " << Report(r));
  CHECK(y.held_out_nll.back() < y.held_out_nll.front());
  CHECK(r.real_nll < r.perturbed_nll);
  CHECK(r.real_beats_own_perturbed > 0.95);
  CHECK(r.auroc_impossible >= 0.95);
  for (double a : r.auroc_kind) CHECK(a >= 0.9);
}

TEST_CASE(
    "bandai: the shipped prior (models/prior-bandai) reproduces its card and separates poses") {
  const std::string dir = std::string(MOTIONFORK_SOURCE_DIR) + "/models/prior-bandai";
  const Bandai* b = LoadBandai();
  if (!b) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  REQUIRE(std::filesystem::exists(dir + "/prior.yaml"));
  PinThreads(1);
  const PosePrior prior = LoadPosePrior(dir);
  prior.CheckSkeleton(*b->skeleton);
  const PriorData data = MakePriorData(b->dataset, prior.config().training);
  const PriorTrainingSummary& y = prior.summary();
  // The bundle's figures come from this data: same frames, same NLLs.
  CHECK(y.train_frames == data.train.size());
  CHECK(y.held_out_frames == data.held_out.size());
  CHECK(y.test_frames == data.test.size());
  CHECK(MeanNll(prior, data.held_out) == Approx(y.held_out_nll.back()).margin(1e-6));
  CHECK(MeanNll(prior, data.test) == Approx(y.test_nll).margin(1e-6));
  const Separation r = Separate(prior, data.test, *b->skeleton, 5);
  WARN("shipped prior: held-out NLL " << y.held_out_nll.back() << ", test NLL " << y.test_nll
                                      << "; " << Report(r));
  // Samples (the CLI's default chain) score like real poses: few above the held-out 99th
  // percentile.
  auto share_above_q99 = [&](const Motion& m) {
    const std::vector<double> lp = prior.LogProb(m);
    return std::count_if(lp.begin(), lp.end(), [&](double v) { return -v > y.held_out_nll_q99; }) /
           static_cast<double>(lp.size());
  };
  const double raw = share_above_q99(prior.Sample(1000, 0, 1.0, {}, 30.0, 0));
  const double chain = share_above_q99(prior.Sample(1000, 0));
  WARN("samples above the held-out 99th percentile NLL: "
       << 100 * raw << "% of raw flow samples, " << 100 * chain
       << "% after 1000 Metropolis-Hastings steps");
  CHECK(chain < 0.05);
  CHECK(r.real_nll < r.perturbed_nll);
  CHECK(r.real_beats_own_perturbed > 0.95);
  CHECK(r.auroc_impossible >= 0.95);
  for (double a : r.auroc_kind) CHECK(a >= 0.9);
}
