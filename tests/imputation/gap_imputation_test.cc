// Imputation over whole motions, the HG-VAE beside the classical fills: settings, masks and the
// experiment, on a tiny HG-VAE trained in code and synthetic walks.
#include "imputation/gap_imputation.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <iterator>
#include <tuple>
#include <utility>

#include "bundle/hgvae_bundle.h"
#include "imputation/interpolation_fill.h"
#include "imputation/motion_imputation.h"
#include "imputation/refiner_adaptation.h"
#include "imputation/refiner_fills.h"
#include "imputation/tiny_hgvae.h"
#include "imputation/training/gaussian_fitting.h"
#include "imputation/training/refiner_calibration.h"
#include "test_support.h"

using namespace motionfork;

namespace {

const HgvaeModel& TinyModel() {
  static testing::TempDir dir;
  static const HgvaeModel model = [] {
    testing::WriteTinyHgvaeBundle(dir.file("m"), 8, 6);
    return LoadHgvaeModel(dir.file("m"));
  }();
  return model;
}

const GapSetting* Named(const std::vector<GapSetting>& settings, const std::string& name) {
  for (const GapSetting& s : settings) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

}  // namespace

TEST_CASE("gap settings: random shares, gaps of 1 frame to 2 s and whole clips of each group") {
  const auto skeleton = testing::MakeHumanoid();
  const std::vector<GapSetting> s = StandardGapSettings(*skeleton, 30);
  // 4 random shares; 4 groups (left hand, left arm, legs, upper) of 5 gaps and a whole clip.
  CHECK(s.size() == 4 + 4 * 6);
  REQUIRE(Named(s, "random 10%"));
  CHECK(Named(s, "random 10%")->share == 0.1);
  REQUIRE(Named(s, "left hand, 1 frame gap"));
  CHECK(Named(s, "left hand, 1 frame gap")->joints == std::vector<int>{skeleton->Index("Hand_L")});
  REQUIRE(Named(s, "left arm, 0.5 s gap"));
  CHECK(Named(s, "left arm, 0.5 s gap")->gap_frames == 15);
  CHECK(Named(s, "left arm, 0.5 s gap")->joints.size() == 3);
  REQUIRE(Named(s, "legs, 2 s gap"));
  CHECK(Named(s, "legs, 2 s gap")->gap_frames == 60);
  REQUIRE(Named(s, "upper, whole clip"));
  CHECK(Named(s, "upper, whole clip")->gap_frames == 0);
  for (const GapSetting& g : s) {
    for (int j : g.joints) CHECK(j != 0);  // the root is never missing
  }
  // At 4 Hz a quarter second is one frame: that gap is listed once.
  const std::vector<GapSetting> slow = StandardGapSettings(*skeleton, 4);
  CHECK(slow.size() == 4 + 4 * 5);
}

TEST_CASE("gap masks: exact random shares without the root, bracketed gaps, reproducible") {
  const int T = 50, J = 17;
  const GapSetting random{"random 10%", 0.1, {}, 0};
  const std::vector<uint8_t> m = GapMask(random, T, J, 5);
  int missing = 0;
  for (int t = 0; t < T; ++t) {
    for (int v = 0; v < 3 * J; ++v) {
      missing += m[t * 3 * J + v];
      if (v < 3) CHECK(m[t * 3 * J + v] == 0);
    }
  }
  CHECK(missing == static_cast<int>(std::lround(0.1 * T * 3 * (J - 1))));
  CHECK(GapMask(random, T, J, 5) == m);
  CHECK(GapMask(random, T, J, 6) != m);
  const GapSetting gap{"gap", 0, {3, 13}, 10};
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const std::vector<uint8_t> g = GapMask(gap, T, J, seed);
    int first = -1, last = -1;
    for (int t = 0; t < T; ++t) {
      if (g[t * 3 * J + 13 * 3]) {
        if (first < 0) first = t;
        last = t;
      }
    }
    CHECK(last - first + 1 == 10);
    CHECK(first >= 1);
    CHECK(last <= T - 2);
    CHECK(g[first * 3 * J + 3 * 3 + 2] == 1);
  }
  CHECK(GapMask(gap, 11, J, 0).empty());  // 10 frames cannot be bracketed in 11
  CHECK_FALSE(GapMask(gap, 12, J, 0).empty());
  const GapSetting whole{"whole", 0, {13}, 0};
  const std::vector<uint8_t> w = GapMask(whole, T, J, 0);
  for (int t = 0; t < T; ++t) CHECK(w[t * 3 * J + 13 * 3 + 1] == 1);
}

TEST_CASE(
    "gap experiment: every method fills, observed values stay, interpolation wins short gaps") {
  const HgvaeModel& model = TinyModel();
  const std::vector<Motion> motions = {testing::MakeWalkingMotion(60, 30, 1),
                                       testing::MakeWalkingMotion(45, 30, 2)};
  const std::vector<GapSetting> settings = {{"random 10%", 0.1, {}, 0},
                                            {"left hand, 1 frame gap", 0, {13}, 1},
                                            {"left arm, whole clip", 0, {11, 12, 13}, 0},
                                            {"too long", 0, {13}, 100}};
  // Each method keeps observed values and fills every missing one.
  const std::vector<uint8_t> mask = GapMask(settings[0], 60, 17, 3);
  for (FillMethod m : AllFillMethods()) {
    INFO(FillMethodName(m));
    if (m == FillMethod::kRefiner) {  // this bundle has none
      CHECK_THROWS_WITH(FillMotion(m, model, motions[0], mask, ImputeOptions{}),
                        Catch::Contains("hgvae refine"));
      continue;
    }
    const std::vector<float> f = FillMotion(m, model, motions[0], mask, ImputeOptions{});
    REQUIRE(f.size() == mask.size());
    for (size_t i = 0; i < f.size(); ++i) {
      if (!mask[i]) CHECK(f[i] == motions[0].positions()[i]);
      CHECK(std::isfinite(f[i]));
    }
  }
  int reported = 0;
  const std::vector<GapFigure> figures =
      GapExperiment(model, motions, settings, ImputeOptions{}, 9, [&](int d, int t) {
        CHECK(t == 4);
        reported = d;
      });
  CHECK(reported == 4);
  REQUIRE(figures.size() == 4);
  for (int s = 0; s < 3; ++s) {
    INFO(settings[s].name);
    CHECK(figures[s].motions == 2);
    REQUIRE(figures[s].rms_cm.size() == AllFillMethods().size());
    for (FillMethod m : AllFillMethods())
      CHECK(std::isfinite(figures[s].rms_cm[static_cast<int>(m)]) == (m != FillMethod::kRefiner));
    CHECK(figures[s].best_baseline() < static_cast<int>(FillMethod::kHgvae));
  }
  CHECK(figures[1].missing_values == 2 * 3);
  // A one-frame gap in a smooth walk: linear interpolation far below the mean pose; the HG-VAE
  // from the spline keeps its best step, which may be the spline itself (step 0).
  CHECK(figures[1].rms_cm[1] < 0.2 * figures[1].rms_cm[0]);
  CHECK(figures[1].rms_cm[5] < figures[1].rms_cm[4]);
  // Nothing to bracket: no clip, no figure.
  CHECK(figures[3].motions == 0);
  CHECK(std::isnan(figures[3].rms_cm[0]));
  // The same seed, the same figures.
  const std::vector<GapFigure> again = GapExperiment(model, motions, settings, ImputeOptions{}, 9);
  for (size_t m = 0; m < static_cast<size_t>(FillMethod::kRefiner); ++m)  // the refiner: NaN
    CHECK(again[0].rms_cm[m] == figures[0].rms_cm[m]);
}

TEST_CASE("imputation from an interpolation: with no Adam step, the interpolation itself") {
  const HgvaeModel& model = TinyModel();
  const Motion m = testing::MakeWalkingMotion(40, 30, 4);
  const std::vector<uint8_t> mask = GapMask({"gap", 0, {12, 13}, 6}, 40, 17, 1);
  ImputeOptions none;
  none.steps = 0;
  for (ImputeStart start : {ImputeStart::kLinear, ImputeStart::kSpline}) {
    INFO(ToString(start));
    none.start = start;
    const std::vector<float> filled = ImputeMotion(model, m, mask, none).motion.positions();
    const std::vector<float> interpolated = InterpolateMissing(
        m.positions(), mask, 17,
        start == ImputeStart::kLinear ? Interpolation::kLinear : Interpolation::kCubicSpline,
        TrainingMeanPose(model));
    for (size_t i = 0; i < mask.size(); ++i)
      CHECK(filled[i] == Approx(interpolated[i]).margin(1e-5));
  }
  // From the mean: the mean pose about the root.
  none.start = ImputeStart::kMean;
  const std::vector<float> mean = ImputeMotion(model, m, mask, none).motion.positions();
  const std::vector<float> pose = TrainingMeanPose(model);
  const size_t at = [&] {
    for (size_t i = 0; i < mask.size(); ++i)
      if (mask[i]) return i;
    return size_t{0};
  }();
  CHECK(mean[at] == Approx(m.positions()[at - at % 51 + at % 3] + pose[at % 51]).margin(1e-5));
}

TEST_CASE(
    "the imputation refiner: trained from a bundle, it fills every gap, observed values kept") {
  testing::TempDir dir;
  HgvaeTrainConfig cfg = testing::TinyHgvaeConfig(8, 1);
  cfg.refiner.model = {8, 20, 5, {1, 2}, 3, false};
  cfg.refiner.training.epochs = 3;
  cfg.refiner.training.windows_per_epoch = 128;
  cfg.refiner.training.batch_size = 16;
  const HgvaeData data = testing::TinyHgvaeData(12, 60);
  testing::WriteTinyHgvaeBundle(dir.file("m"), 8, 2);
  const HgvaeTrainSummary s = RefineHgvae(cfg, dir.file("m"), data, dir.file("r"), {});
  CHECK(s.epochs_done == 3);
  const HgvaeModel model = LoadHgvaeModel(dir.file("r"));
  REQUIRE(model.has_refiner());
  CHECK(model.manifest().impute.start == ImputeStart::kRefiner);
  CHECK(model.manifest().impute.steps == 0);
  CHECK_FALSE(model.manifest().refiner.smooth_start);
  const Motion motion = testing::MakeWalkingMotion(50, 30, 7);
  for (const GapSetting& setting :
       std::vector<GapSetting>{{"random 30%", 0.3, {}, 0},
                               {"arm gap", 0, {11, 12, 13}, 12},
                               {"arm, whole clip", 0, {11, 12, 13}, 0}}) {
    INFO(setting.name);
    const std::vector<uint8_t> mask = GapMask(setting, 50, 17, 5);
    const std::vector<float> filled =
        ImputeMotion(model, motion, mask, model.manifest().impute).motion.positions();
    CHECK(FillMotion(FillMethod::kRefiner, model, motion, mask, ImputeOptions{}) == filled);
    for (size_t i = 0; i < mask.size(); ++i) {
      REQUIRE(std::isfinite(filled[i]));
      if (!mask[i]) CHECK(filled[i] == motion.positions()[i]);
    }
  }
  const std::vector<GapFigure> figures =
      GapExperiment(model, {motion}, {{"arm gap", 0, {11, 12, 13}, 12}}, ImputeOptions{}, 1);
  CHECK(std::isfinite(figures[0].rms_cm[static_cast<int>(FillMethod::kRefiner)]));
  // Resuming a finished run trains nothing more and keeps the bundle.
  CHECK(RefineHgvae(cfg, dir.file("m"), data, dir.file("r"), {}).epochs_done == 0);

  // Calibration on the held-out clips: per bucket the least-squares weights in [0, 1], so the
  // summed relative error is at most the refiner's and the spline's (weights 1, 0 and 0, 0).
  CHECK_THROWS_AS(CalibrateHgvaeBundle(dir.file("r"), data.held_out.poses, 1, dir.file("r")),
                  std::invalid_argument);  // never over its input
  const RefinerCalibration c =
      CalibrateHgvaeBundle(dir.file("r"), data.held_out.poses, 1, dir.file("c"));
  REQUIRE(c.blend.refiner.size() == static_cast<size_t>(kRefinerGapBuckets));
  REQUIRE(c.blend.local.size() == static_cast<size_t>(kRefinerGapBuckets));
  REQUIRE_FALSE(c.settings.empty());
  double spline = 0, refiner = 0, calibrated = 0, adapted = 0, bones = 0;
  for (const RefinerCalibration::Setting& x : c.settings) {
    spline += 1;
    refiner += std::pow(x.refiner_cm / x.spline_cm, 2);
    calibrated += std::pow(x.calibrated_cm / x.spline_cm, 2);
    adapted += std::pow(x.adapted_cm / x.spline_cm, 2);
    bones += std::pow(x.kept_cm / x.spline_cm, 2);
  }
  CHECK(calibrated <= refiner + 1e-9);
  CHECK(calibrated <= spline + 1e-9);
  CHECK(c.blend.keep_bones == (bones < adapted));
  // Every prior was scored; each gap length class took the one with its lowest cross-fitted sum,
  // which together are at most the best single prior's (0: no adaptation).
  REQUIRE(c.adapt_scores.size() == std::size(kAdaptPriors));
  REQUIRE(c.length_priors.size() == static_cast<size_t>(kRefinerGapLengths));
  double best = INFINITY;
  for (const auto& [prior, score] : c.adapt_scores) {
    CHECK(std::isfinite(score));
    best = std::min(best, score);
  }
  CHECK(c.length_score <= best + 1e-9);
  for (int k = 0; k < kRefinerGapBuckets; ++k)
    CHECK(AdaptValues(c.blend, k) == c.length_priors[k / 6]);
  if (!AdaptsToMotion(c.blend)) {
    CHECK(c.blend.adapt_values.empty());
    CHECK(adapted == Approx(calibrated).epsilon(1e-9));
  }
  for (double w : c.blend.refiner) CHECK((w >= 0 && w <= 1));
  for (double w : c.blend.local) CHECK((w >= 0 && w <= 1));
  HgvaeManifest cm;
  HgvaeNet net = LoadHgvaeBundle(dir.file("c"), &cm);
  CHECK(cm.refiner_weights == c.blend.refiner);
  CHECK(cm.refiner_local_weights == c.blend.local);
  CHECK(cm.refiner_keep_bones == c.blend.keep_bones);
  CHECK(cm.refiner_adapt_values == c.blend.adapt_values);
  CHECK(RefinerCalibrationText(c, "OUT").find("gap 1, slow, sparse") != std::string::npos);
  // The last stage: every lambda scored on the whole clips and on the histories, each the lowest
  // (0, no smoothing, among them), written to the bundle.
  REQUIRE(c.smoothing.bracketed.size() == std::size(kSmoothingLambdas));
  REQUIRE(c.smoothing.one_sided.size() == std::size(kSmoothingLambdas));
  CHECK(c.smoothing.histories > 0);
  for (const auto& [lambda, score] : c.smoothing.bracketed) {
    REQUIRE(std::isfinite(score));
    if (lambda == c.smoothing.chosen.bracketed) CHECK(score <= c.smoothing.bracketed[0].second);
  }
  for (const auto& [lambda, score] : c.smoothing.one_sided) CHECK(std::isfinite(score));
  for (const auto* scores : {&c.smoothing.bracketed, &c.smoothing.one_sided}) {
    double lowest = INFINITY, at = -1;
    for (const auto& [lambda, score] : *scores)
      if (score < lowest) std::tie(lowest, at) = std::make_pair(score, lambda);
    CHECK(at == (scores == &c.smoothing.bracketed ? c.smoothing.chosen.bracketed
                                                  : c.smoothing.chosen.one_sided));
  }
  CHECK(c.blend.smoothing.bracketed == c.smoothing.chosen.bracketed);
  CHECK(c.blend.smoothing.one_sided == c.smoothing.chosen.one_sided);
  CHECK(cm.refiner_smoothing.bracketed == c.smoothing.chosen.bracketed);
  CHECK(cm.refiner_smoothing.one_sided == c.smoothing.chosen.one_sided);
  CHECK(RefinerCalibrationText(c, "OUT").find("smooth the filled values: bracketed") !=
        std::string::npos);
  // The smoothing keys round-trip and are refused when negative or unknown.
  {
    HgvaeManifest s = cm;
    s.refiner_smoothing = {2.5, 30};
    std::ofstream(dir.file("smooth.yaml")) << FormatHgvaeManifest(s);
    const HgvaeManifest back = LoadHgvaeManifest(dir.file("smooth.yaml"));
    CHECK(back.refiner_smoothing.bracketed == 2.5);
    CHECK(back.refiner_smoothing.one_sided == 30);
    const std::string text = FormatHgvaeManifest(s);
    auto refused = [&](const std::string& value, const std::string& why) {
      std::string edited = text;
      const size_t at = edited.find("refiner_smooth: {");
      REQUIRE(at != std::string::npos);
      edited.replace(at, edited.find('}', at) + 1 - at, "refiner_smooth: " + value);
      std::ofstream(dir.file("edited.yaml")) << edited;
      CHECK_THROWS_WITH(LoadHgvaeManifest(dir.file("edited.yaml")), Catch::Contains(why));
    };
    refused("{bracketed: -1, one_sided: 3}", "refiner_smooth: expected finite numbers >= 0");
    refused("{bracket: 1}", "refiner_smooth: unknown key 'bracket'");
    refused("3", "refiner_smooth: expected a map");
  }
  // The one-sided values' Gaussian: fitted on the training clips, measured on held-out
  // histories, in the bundle (checksummed) when it lowers their error, and used by Refine.
  {
    CHECK_THROWS_AS(FitGaussianIntoBundle(dir.file("c"), data.train.poses, data.held_out.poses, 1,
                                          dir.file("c")),
                    std::invalid_argument);
    const GaussianFit e = FitGaussianIntoBundle(dir.file("c"), data.train.poses,
                                                data.held_out.poses, 1, dir.file("e"));
    CHECK(e.gaussian.frames == 8);
    CHECK(e.gaussian.coords == 48);
    REQUIRE(e.shares.size() == std::size(kSmoothingShares));
    for (const GaussianFit::Share& sh : e.shares) {
      CHECK(sh.values > 0);
      CHECK(sh.one_sided > 0);
      for (int k = 0; k < 3; ++k) CHECK(std::isfinite(sh.all_cm[k] + sh.one_sided_cm[k]));
    }
    CHECK(e.chosen == (std::min(e.score[0], e.score[1]) < 3));
    CHECK(e.scope ==
          (e.score[1] < e.score[0] ? GaussianScope::kShortMotions : GaussianScope::kOneSided));
    CHECK(GaussianFitText(e, "OUT").find("one-sided") != std::string::npos);
    CHECK(LoadHgvaeModel(dir.file("e")).manifest().refiner_gaussian.enabled() == e.chosen);
    // (The tiny walks are smooth enough that the smoothing's extrapolation wins there.) A bundle
    // with the Gaussian whichever won: saved with its checksum, loaded, applied last by Refine.
    HgvaeManifest gm = cm;
    gm.refiner_gaussian = {"window_gaussian.npy",
                           8,
                           48,
                           e.gaussian.windows,
                           GaussianScope::kShortMotions,
                           std::make_shared<const WindowGaussian>(e.gaussian)};
    SaveHgvaeBundle(dir.file("g"), gm, net);
    const HgvaeModel ends = LoadHgvaeModel(dir.file("g"));
    REQUIRE(ends.manifest().refiner_gaussian.model);
    CHECK(ends.manifest().refiner_gaussian.model->windows == e.gaussian.windows);
    // A motion with its last frame's left hand missing: the Gaussian's estimate there.
    std::vector<uint8_t> last(50 * 17 * 3, 0);
    for (int v = 0; v < 3; ++v) last[(49 * 17 + 13) * 3 + v] = 1;
    const RefinerFills lf =
        MakeRefinerFills(motion.skeleton(), motion.positions(), last, TrainingMeanPose(ends));
    const std::vector<float> with = ends.Refine(lf);
    ImputationBlend plain = ends.calibrated_blend();
    plain.gaussian = nullptr;
    const RawRefiner raw = [&](const RefinerFills& p) { return ends.Refine(p, false); };
    const std::vector<float> without = BlendRefinerFills(
        motion.skeleton(), lf, raw(lf), AdaptToMotion(motion.skeleton(), lf, raw, plain));
    CHECK(with != without);
    CHECK(ends.manifest().refiner_gaussian.scope == GaussianScope::kShortMotions);
    CHECK(with == FillFromWindowGaussian(*ends.manifest().refiner_gaussian.model, without, lf.mask,
                                         GaussianScope::kShortMotions));
    // A damaged Gaussian file is refused by its checksum, naming it.
    std::ofstream(dir.file("g/window_gaussian.npy"), std::ios::app) << "x";
    CHECK_THROWS_WITH(LoadHgvaeModel(dir.file("g")), Catch::Contains("window_gaussian.npy"));
  }
  // Weights 0 keep the spline exactly; the uncalibrated refiner ignores them.
  cm.refiner_weights.assign(kRefinerGapBuckets, 0.0);
  cm.refiner_local_weights.assign(kRefinerGapBuckets, 0.0);
  cm.refiner_keep_bones = false;
  cm.refiner_adapt_values.clear();
  cm.refiner_smoothing = {};
  const HgvaeModel zero = HgvaeModel::FromNet(cm, net);
  const std::vector<uint8_t> mask = GapMask({"arm gap", 0, {11, 12, 13}, 12}, 50, 17, 5);
  const RefinerFills f =
      MakeRefinerFills(motion.skeleton(), motion.positions(), mask, TrainingMeanPose(zero));
  const std::vector<float> kept = zero.Refine(f);
  for (size_t i = 0; i < kept.size(); ++i) REQUIRE(kept[i] == Approx(f.spline[i]).margin(1e-6));
  CHECK(zero.Refine(f, false) == model.Refine(f));
  // Local weights 1 (and refiner weights 0): the local polynomial; the keys round-trip.
  cm.refiner_local_weights.assign(kRefinerGapBuckets, 1.0);
  cm.refiner_keep_bones = true;
  const std::vector<float> local = HgvaeModel::FromNet(cm, net).Refine(f);
  HgvaeManifest again;
  {
    std::ofstream(dir.file("again.yaml")) << FormatHgvaeManifest(cm);
    again = LoadHgvaeManifest(dir.file("again.yaml"));
  }
  CHECK(again.refiner_local_weights == cm.refiner_local_weights);
  CHECK(again.refiner_keep_bones);
  // Adapted to the motion: the observed values stay as they are, the missing ones move off the
  // local polynomial where the probes say so; the prior round-trips, a negative one is refused.
  cm.refiner_adapt_values = {10};
  const std::vector<float> adapted_fill = HgvaeModel::FromNet(cm, net).Refine(f);
  for (size_t i = 0; i < f.mask.size(); ++i) {
    REQUIRE(std::isfinite(adapted_fill[i]));
    if (!f.mask[i]) CHECK(adapted_fill[i] == Approx(f.spline[i]).margin(1e-6));
  }
  {
    std::ofstream(dir.file("again.yaml")) << FormatHgvaeManifest(cm);
    CHECK(LoadHgvaeManifest(dir.file("again.yaml")).refiner_adapt_values ==
          std::vector<double>{10});
    const std::string text = FormatHgvaeManifest(cm);
    auto refused = [&](const std::string& value) {
      std::string edited = text;
      edited.replace(edited.find("refiner_adapt_values: 10"), 24, "refiner_adapt_values: " + value);
      std::ofstream(dir.file("edited.yaml")) << edited;
      CHECK_THROWS_WITH(LoadHgvaeManifest(dir.file("edited.yaml")),
                        Catch::Contains("refiner_adapt_values: expected a finite number >= 0"));
    };
    refused("-1");
    refused("[1, 2, 3]");  // neither one value nor one per gap length
    refused("[1, 2, 3, 4, 5, 6, 7, -8]");
    // One per gap length round-trips as a list.
    cm.refiner_adapt_values = {0, 3, 10, 30, 100, 300, 1000, 100};
    std::ofstream(dir.file("again.yaml")) << FormatHgvaeManifest(cm);
    CHECK(LoadHgvaeManifest(dir.file("again.yaml")).refiner_adapt_values ==
          cm.refiner_adapt_values);
    cm.refiner_adapt_values = {10};
  }
  double moved = 0;
  for (size_t i = 0; i < local.size(); ++i) moved += std::abs(local[i] - f.spline[i]);
  CHECK(moved > 0);
  // A bundle whose weights are not one per bucket is refused, naming the key.
  std::string text = FormatHgvaeManifest(cm);
  text.replace(text.find("refiner_weights: ["), 18, "refiner_weights: [1, ");
  std::ofstream(dir.file("bad.yaml")) << text;
  CHECK_THROWS_WITH(LoadHgvaeManifest(dir.file("bad.yaml")),
                    Catch::Contains("refiner_weights: expected 48"));
}
