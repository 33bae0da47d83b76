// Motion corruptions, windows and figures of the denoising module (no LibTorch).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/motion_noise.h"
#include "denoise/denoise_metrics.h"
#include "denoise/dvae_windows.h"
#include "denoise/refiner_blend.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;

TEST_CASE("noise specs parse and bad ones name the expected forms") {
  const NoiseSpec g = ParseNoiseSpec("gaussian:0.05");
  CHECK(g.kind == NoiseSpec::Kind::kGaussian);
  CHECK(g.sigma == Approx(0.05));
  const NoiseSpec o = ParseNoiseSpec("outliers:0.1,0.3");
  CHECK(o.kind == NoiseSpec::Kind::kOutliers);
  CHECK(o.rate == Approx(0.1));
  CHECK(o.sigma == Approx(0.3));
  CHECK(ParseNoiseSpec("jitter:0.02").kind == NoiseSpec::Kind::kJitter);
  CHECK_THROWS_WITH(ParseNoiseSpec("gauss:0.1"),
                    Contains("unknown kind") && Contains("gaussian:S"));
  CHECK_THROWS_WITH(ParseNoiseSpec("gaussian"), Contains("no ':'"));
  CHECK_THROWS_WITH(ParseNoiseSpec("gaussian:abc"), Contains("not a number"));
  CHECK_THROWS_WITH(ParseNoiseSpec("outliers:1.5,0.1"), Contains("P must be in [0, 1]"));
  CHECK_THROWS_WITH(ParseNoiseSpec("gaussian:-1"), Contains("S must be"));
}

TEST_CASE("noise kinds have the documented statistics") {
  const Motion clean = testing::MakeWalkingMotion(400);
  const int J = clean.num_joints();
  SECTION("gaussian: every value, standard deviation S") {
    const Motion n = AddNoise(clean, ParseNoiseSpec("gaussian:0.05"), 1);
    double sq = 0;
    for (size_t i = 0; i < n.positions().size(); ++i)
      sq += std::pow(n.positions()[i] - clean.positions()[i], 2);
    CHECK(std::sqrt(sq / n.positions().size()) == Approx(0.05).epsilon(0.03));
  }
  SECTION("jitter: one offset per frame, shared by every joint") {
    const Motion n = AddNoise(clean, ParseNoiseSpec("jitter:0.05"), 2);
    for (int t = 0; t < 10; ++t) {
      const float d0 = n.at(t, 0)[1] - clean.at(t, 0)[1];
      CHECK(d0 != 0.0f);
      for (int j = 1; j < J; ++j)
        CHECK(n.at(t, j)[1] - clean.at(t, j)[1] == Approx(d0).margin(1e-5));
    }
  }
  SECTION("outliers: about P of the joints move, the rest stay") {
    const Motion n = AddNoise(clean, ParseNoiseSpec("outliers:0.1,0.3"), 3);
    int moved = 0;
    for (int t = 0; t < clean.num_frames(); ++t) {
      for (int j = 0; j < J; ++j) moved += n.at(t, j)[0] != clean.at(t, j)[0];
    }
    CHECK(double(moved) / (clean.num_frames() * J) == Approx(0.1).margin(0.02));
  }
  SECTION("the same seed gives the same noise") {
    CHECK(AddNoise(clean, ParseNoiseSpec("gaussian:0.02"), 9).positions() ==
          AddNoise(clean, ParseNoiseSpec("gaussian:0.02"), 9).positions());
    CHECK(AddNoise(clean, ParseNoiseSpec("gaussian:0.02"), 9).positions() !=
          AddNoise(clean, ParseNoiseSpec("gaussian:0.02"), 10).positions());
  }
}

TEST_CASE("windows cover every frame and blending unchanged windows gives the sequences back") {
  const std::vector<int> frames = {100, 30, 7, 31};
  const std::vector<WindowCut> cuts = CutWindows(frames, 30, 15);
  std::vector<int> covered_100(100, 0);
  for (const WindowCut& c : cuts) {
    CHECK(c.start + c.length <= frames[c.sequence]);
    if (c.sequence == 0) {
      CHECK(c.length == 30);
      for (int t = c.start; t < c.start + c.length; ++t) covered_100[t] = 1;
    }
    if (c.sequence == 2)
      CHECK(c.length == 7);  // shorter than the window: one window of its own length
  }
  for (int v : covered_100) CHECK(v == 1);
  CHECK_THROWS_WITH(CutWindows({1}, 30, 15), Contains("at least 2 frames"));

  const Motion a = testing::MakeWalkingMotion(100, 30, 1),
               b = testing::MakeWalkingMotion(31, 30, 2);
  std::vector<std::vector<float>> seqs = {a.positions(), b.positions()};
  const int J = a.num_joints();
  std::vector<WindowCut> cut = CutWindows({100, 31}, 30, 15);
  std::vector<std::vector<float>> values;
  for (WindowCut& c : cut) values.push_back(WindowValues(seqs[c.sequence].data(), J, &c));
  // Window values are relative to the window's mean root position.
  double root_mean = 0;
  for (int t = 0; t < cut[0].length; ++t) root_mean += values[0][t * J * 3 + 0];
  CHECK(root_mean / cut[0].length == Approx(0).margin(1e-5));
  const auto back = BlendWindows(cut, values, {100, 31}, J);
  for (size_t s = 0; s < seqs.size(); ++s) {
    REQUIRE(back[s].size() == seqs[s].size());
    for (size_t i = 0; i < seqs[s].size(); ++i)
      CHECK(back[s][i] == Approx(seqs[s][i]).margin(1e-5));
  }
}

TEST_CASE("denoising figures: error, acceleration and the smoothing baseline") {
  const int J = 2, T = 20;
  std::vector<float> line(T * J * 3), shifted(T * J * 3);
  for (int t = 0; t < T; ++t) {
    for (int j = 0; j < J; ++j) {
      line[(t * J + j) * 3 + 0] = 0.1f * t;  // constant velocity
      shifted[(t * J + j) * 3 + 0] = 0.1f * t;
      shifted[(t * J + j) * 3 + 1] = 0.03f;
    }
  }
  CHECK(MeanJointError(line, shifted) == Approx(0.03).margin(1e-6));
  CHECK(MeanAcceleration(line, J, 30) == Approx(0).margin(1e-3));
  std::vector<float> bumped = line;
  bumped[(10 * J) * 3 + 2] = 0.01f;  // joint 0, frame 10: 1 cm out
  // |a| at frames 9, 10, 11: 1, 2, 1 cm -> (4 cm) * 30^2 / ((T - 2) * J)
  CHECK(MeanAcceleration(bumped, J, 30) == Approx(0.04 * 900 / (18 * 2)).epsilon(1e-3));
  const std::vector<float> smooth = GaussianSmooth(line, J, 2.0);
  for (int t = 6; t < T - 6; ++t)
    CHECK(smooth[t * J * 3] == Approx(line[t * J * 3]).margin(1e-5));  // 3 sigma from the edges
  const std::vector<float> smoothed_bump = GaussianSmooth(bumped, J, 2.0);
  CHECK(std::abs(smoothed_bump[(10 * J) * 3 + 2]) < 0.005);
}

TEST_CASE("refiner blend: bins of the local correction size, the blend, least-squares weights") {
  CHECK(RefinerBlendBin(0) == 0);
  CHECK(RefinerBlendBin(0.3) == 1);
  CHECK(RefinerBlendBin(1.0) == 4);
  CHECK(RefinerBlendBin(100) == kRefinerBlendBins - 1);
  CHECK(RefinerBlendBinName(3) == "0.75-1 cm");
  CHECK(RefinerBlendBinName(kRefinerBlendBins - 1) == ">= 5 cm");
  // Two joints, 40 frames: the refined motion 2 cm off in every value of frames 20-39.
  const int J = 2, T = 40;
  std::vector<float> input(T * J * 3, 0.0f), refined = input;
  for (int k = 20 * J * 3; k < T * J * 3; ++k) refined[k] = 0.02f;
  const std::vector<double> size = LocalCorrectionCm(input, refined, J, 2);
  CHECK(size[0] == Approx(0));
  CHECK(size[39] == Approx(100 * std::sqrt(3 * 0.0004)));          // sqrt(3) x 2 cm per joint
  CHECK(size[20] == Approx(100 * std::sqrt(3 * 0.0004 * 3 / 5)));  // 3 of its 5 frames
  // The input is smooth (roughness 0: bin 0), so bin 0's weight applies.
  CHECK(InputRoughnessCm(input, J) == std::vector<double>(T, 0.0));
  RefinerBlend blend;
  blend.weights.assign(kRefinerBlendBins, 1.0);
  blend.weights[0] = 0.5;
  const std::vector<float> out = BlendRefined(input, refined, J, blend);
  CHECK(out[30 * J * 3] == Approx(0.01f));
  CHECK(BlendRefined(input, refined, J, {}) == refined);
  RefinerBlend one_weight;
  one_weight.weights = {1.0};
  CHECK_THROWS_AS(BlendRefined(input, refined, J, one_weight), std::invalid_argument);
  CHECK_THROWS_AS(BlendRefined(input, std::vector<float>(6), J, blend), std::invalid_argument);
  // A smoothed base where rough: a smooth input stays itself.
  blend.sigma = 1.5;
  CHECK(BlendRefined(input, refined, J, blend)[30 * J * 3] == Approx(0.01f));
  // A clean setting (the refiner off the truth) and a noisy one (a frame-to-frame zigzag, the
  // refiner right): the fit keeps none of the correction where the smooth input falls and all of
  // it where the rough one does.
  RefinerBlendFit fit;
  std::vector<float> noisy(T * J * 3);
  for (int t = 0; t < T; ++t)
    for (int k = 0; k < J * 3; ++k) noisy[t * J * 3 + k] = t % 2 ? 0.05f : -0.05f;
  const std::vector<double> rough = InputRoughnessCm(noisy, J);
  CHECK(rough[20] > 5.0);  // ~0.98 x 5 cm per coordinate, x sqrt(3) per joint
  fit.AddSetting({input}, {std::vector<float>(T * J * 3, 0.004f)}, {input}, J);
  fit.AddSetting({noisy}, {input}, {input}, J);
  const std::vector<double> weights = fit.Blend().weights;
  CHECK(fit.Error() == Approx(0).margin(1e-12));  // both settings fitted exactly
  CHECK(weights[0] == 0.0);                       // smooth: clean
  CHECK(weights[kRefinerBlendBins - 1] == 1.0);   // rough: noisy
  CHECK(weights[1] == 1.0);                       // no data
}

TEST_CASE("roughness against a Savitzky-Golay fit: fast smooth motion is not rough, noise is") {
  // One joint on a fast cubic path (metres a frame: 0.1 t - 0.004 t^2 + 0.0001 t^3), then the same
  // with a zigzag of 1 cm.
  const int J = 1, T = 60;
  std::vector<float> path(T * 3), zigzag(T * 3);
  for (int t = 0; t < T; ++t) {
    for (int a = 0; a < 3; ++a) {
      path[t * 3 + a] = static_cast<float>((a + 1) * (0.1 * t - 0.004 * t * t + 1e-4 * t * t * t));
      zigzag[t * 3 + a] = path[t * 3 + a] + (t % 2 ? 0.01f : -0.01f);
    }
  }
  const std::vector<double> gaussian = InputRoughnessCm(path, J, 15, Roughness::kGaussian),
                            fitted = InputRoughnessCm(path, J, 15, Roughness::kSavitzkyGolay),
                            noisy = InputRoughnessCm(zigzag, J, 15, Roughness::kSavitzkyGolay);
  CHECK(gaussian[30] > 0.5);                    // the Gaussian cuts the path's corners
  CHECK(fitted[30] == Approx(0).margin(1e-3));  // a cubic is its own fit
  CHECK(noisy[30] > 1.0);                       // the zigzag is still rough
  CHECK(RoughnessName(Roughness::kSavitzkyGolay) == "savitzky-golay");
  CHECK(InputRoughnessCm(path, J) == gaussian);  // the default: the first bundles' measure
}

TEST_CASE("roughness, median over the joints: a joint's outliers do not make the motion rough") {
  // Five joints on the same cubic path; in `spiky` joint 2 jumps 5 cm in every third frame (a
  // marker the repair missed), in `noisy` every joint zigzags by 1 cm.
  const int J = 5, T = 60;
  std::vector<float> spiky(T * J * 3), noisy(T * J * 3);
  for (int t = 0; t < T; ++t) {
    for (int j = 0; j < J; ++j) {
      for (int a = 0; a < 3; ++a) {
        const size_t k = (static_cast<size_t>(t) * J + j) * 3 + a;
        const float x = static_cast<float>(0.1 * t - 0.004 * t * t + 1e-4 * t * t * t + j);
        spiky[k] = x + (j == 2 && t % 3 == 0 ? 0.05f : 0.0f);
        noisy[k] = x + (t % 2 ? 0.01f : -0.01f);
      }
    }
  }
  const std::vector<double> rms = InputRoughnessCm(spiky, J, 15, Roughness::kSavitzkyGolay),
                            median =
                                InputRoughnessCm(spiky, J, 15, Roughness::kSavitzkyGolayMedian),
                            noisy_rms = InputRoughnessCm(noisy, J, 15, Roughness::kSavitzkyGolay),
                            noisy_median =
                                InputRoughnessCm(noisy, J, 15, Roughness::kSavitzkyGolayMedian);
  CHECK(rms[30] > 1.0);                         // one joint's spikes make every frame rough
  CHECK(median[30] == Approx(0).margin(1e-3));  // the median joint is on its path
  CHECK(noisy_median[30] > 1.0);                // noise on every joint still rough
  CHECK(noisy_median[30] == Approx(noisy_rms[30]).epsilon(1e-4));  // all joints alike
  for (Roughness kind :
       {Roughness::kGaussian, Roughness::kSavitzkyGolay, Roughness::kSavitzkyGolayMedian})
    CHECK(RoughnessNamed(RoughnessName(kind)) == kind);
  CHECK(RoughnessName(Roughness::kSavitzkyGolayMedian) == "savitzky-golay-median");
  CHECK_THROWS_WITH(RoughnessNamed("median"),
                    Catch::Contains("savitzky-golay-median") && Catch::Contains("'median'"));
}

TEST_CASE("refiner blend: smoothing only where the correction says the input was noisy") {
  // One joint, 60 frames of frame-to-frame zigzag; roughness 0 cm in frames 0-19, ramping
  // 0.5 -> 1 cm over 20-39 (0.75 cm at 30) and 2 cm from 40 on.
  const int J = 1, T = 60;
  std::vector<float> zigzag(T * 3);
  for (int t = 0; t < T; ++t)
    for (int a = 0; a < 3; ++a) zigzag[t * 3 + a] = (t % 2 ? 0.01f : -0.01f);
  std::vector<double> size(T, 0.0);
  for (int t = 20; t < 40; ++t) size[t] = 0.5 + 0.5 * (t - 20) / 20.0;
  for (int t = 40; t < T; ++t) size[t] = 2.0;
  const std::vector<float> out = SmoothWhereNoisy(zigzag, size, J, 1.0);
  const std::vector<float> smooth = GaussianSmooth(zigzag, J, 1.0);
  CHECK(out[10 * 3] == zigzag[10 * 3]);                       // clean: untouched
  CHECK(out[50 * 3] == Approx(smooth[50 * 3]).margin(1e-7));  // noisy: smoothed
  CHECK(out[30 * 3] == Approx(0.5 * (zigzag[30 * 3] + smooth[30 * 3])).margin(1e-7));  // halfway
  CHECK(SmoothWhereNoisy(zigzag, size, J, 0) == zigzag);
  // In the blend: output smoothing where noisy lowers the acceleration; a clean frame keeps it.
  const std::vector<float> refined(zigzag.size(), 0.0f);
  RefinerBlend blend;
  blend.weights.assign(kRefinerBlendBins, 0.0);  // keep the input
  const std::vector<float> kept = BlendRefined(zigzag, refined, J, blend);
  blend.smooth = 1.0;
  const std::vector<float> smoothed = BlendRefined(zigzag, refined, J, blend);
  CHECK(kept == zigzag);
  CHECK(MeanAcceleration(smoothed, J, 30) < 0.5 * MeanAcceleration(kept, J, 30));  // every frame
}

TEST_CASE("refiner blend: the output smoothing chosen per motion by its acceleration") {
  // One joint on a sine, fast (period 20 frames) and slow (period 80), with the same noise of
  // 3 mm: the slow motion's accelerations are 16 times smaller beside the same noise, so it is
  // smoothed by a wider Gaussian before its acceleration comes within the bound.
  const int J = 1, T = 160;
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, 0.003f);
  auto sine = [&](double period, bool noisy) {
    std::vector<float> p(T * 3);
    for (int t = 0; t < T; ++t)
      for (int a = 0; a < 3; ++a)
        p[t * 3 + a] = 0.1f * static_cast<float>(std::sin(2 * M_PI * t / period + a)) +
                       (noisy ? noise(rng) : 0.0f);
    return p;
  };
  const std::vector<double> rough(T, 2.0);  // every frame rough: smoothed fully
  // The sigma SmoothToAcceleration chose: the one of kOutputSmoothings that gives its output.
  auto chosen = [&](const std::vector<float>& motion, double bound) {
    const std::vector<float> out = SmoothToAcceleration(motion, rough, J, bound);
    for (double sigma : kOutputSmoothings)
      if (SmoothWhereNoisy(motion, rough, J, sigma) == out) return sigma;
    FAIL("no candidate smoothing gives the output");
    return -1.0;
  };
  const double fast = chosen(sine(20, true), 1.5), slow = chosen(sine(80, true), 1.5);
  CHECK(slow > fast);
  // The chosen output moves within the bound of its reference where a candidate could.
  const std::vector<float> s = sine(80, true);
  const std::vector<float> out = SmoothToAcceleration(s, rough, J, 1.5);
  CHECK(MeanAcceleration(out, J, 1) <=
        1.5 * MeanAcceleration(GaussianSmooth(s, J, kAccelReferenceSigma), J, 1));
  // Where no frame is rough, the motion is kept as it is; a very loose bound smooths nothing.
  CHECK(SmoothToAcceleration(s, std::vector<double>(T, 0.2), J, 1.5) == s);
  CHECK(chosen(s, 100) == 0.0);
  // In the blend, accel_bound replaces the fixed smoothing.
  RefinerBlend blend;
  blend.weights.assign(kRefinerBlendBins, 0.0);  // keep the input
  blend.accel_bound = 1.5;
  const std::vector<double> input_rough = InputRoughnessCm(s, J, 15, blend.roughness);
  CHECK(BlendRefined(s, std::vector<float>(s.size(), 0.0f), J, blend) ==
        SmoothToAcceleration(s, input_rough, J, 1.5));
}
