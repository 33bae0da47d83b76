#include "imputation/window_gaussian.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "core/error.h"

namespace motionfork {
namespace {

// Clips of 3 coordinates [T, 3]: x a sinusoid of random phase and frequency, y = 2 x exactly, z
// independent noise.
std::vector<std::vector<float>> Clips(int count, int T, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> phase(0, 6.283), freq(0.05, 0.3);
  std::normal_distribution<double> noise(0, 0.01);
  std::vector<std::vector<float>> out;
  for (int c = 0; c < count; ++c) {
    const double p = phase(rng), w = freq(rng);
    std::vector<float> clip;
    for (int t = 0; t < T; ++t) {
      const double x = 0.2 * std::sin(w * t + p);
      clip.insert(clip.end(), {static_cast<float>(x), static_cast<float>(2 * x),
                               static_cast<float>(noise(rng))});
    }
    out.push_back(clip);
  }
  return out;
}

TEST_CASE("window Gaussian: the fit is the windows' mean and covariance") {
  // Two clips of 2 frames x 1 coordinate, window 2: windows (0, 1) and (2, 4).
  const WindowGaussian g = FitWindowGaussian({{0, 1}, {2, 4}}, 2, 1);
  CHECK(g.windows == 2);
  CHECK(g.mean == std::vector<double>{1, 2.5});
  // Sample covariance: var(0, 2) = 2, cov = (-1)(-1.5) + (1)(1.5) = 3, var(1, 4) = 4.5.
  CHECK(g.cov[0] == Approx(2));
  CHECK(g.cov[1] == Approx(3));
  CHECK(g.cov[2] == Approx(3));
  CHECK(g.cov[3] == Approx(4.5));
  CHECK_THROWS_AS(FitWindowGaussian({{0, 1}}, 2, 1), std::invalid_argument);     // one window
  CHECK_THROWS_AS(FitWindowGaussian({{0, 1, 2}}, 2, 2), std::invalid_argument);  // not [T, 2]
}

TEST_CASE("window Gaussian: one-sided values from the window's evidence, nothing else touched") {
  const int W = 6, T = 10;
  const WindowGaussian g = FitWindowGaussian(Clips(200, 40, 1), W, 3);
  const std::vector<float> clean = Clips(1, T, 99)[0];
  std::vector<uint8_t> mask(clean.size(), 0);
  std::vector<float> filled = clean;
  auto miss = [&](int t, int v, float value) {
    mask[t * 3 + v] = 1;
    filled[t * 3 + v] = value;
  };
  miss(T - 1, 0, 0.5f);  // x's last frame: y = 2x is observed there, so x is known exactly
  miss(4, 0, 0.5f);      // a bracketed gap: left as filled
  miss(0, 1, 0.5f);      // y's first two frames: one-sided at the start
  miss(1, 1, 0.5f);
  const std::vector<float> out = FillFromWindowGaussian(g, filled, mask, GaussianScope::kOneSided);
  for (size_t i = 0; i < out.size(); ++i)
    if (!mask[i]) REQUIRE(out[i] == clean[i]);  // observed values stay exactly
  CHECK(out[(T - 1) * 3] == Approx(clean[(T - 1) * 3]).margin(1e-3));
  CHECK(out[4 * 3] == 0.5f);
  // y's one-sided values: x is observed in those frames, y = 2 x.
  CHECK(out[1] == Approx(clean[1]).margin(2e-3));
  CHECK(out[3 + 1] == Approx(clean[3 + 1]).margin(2e-3));
  // A coordinate never observed in the window keeps its fill; noise is not made up.
  std::vector<uint8_t> z_gone = mask;
  std::vector<float> z_filled = filled;
  for (int t = 0; t < T; ++t) {
    z_gone[t * 3 + 2] = 1;
    z_filled[t * 3 + 2] = 0.25f;
  }
  const std::vector<float> z_out =
      FillFromWindowGaussian(g, z_filled, z_gone, GaussianScope::kOneSided);
  for (int t = 0; t < T; ++t) CHECK(z_out[t * 3 + 2] == 0.25f);
  // Shorter than the window: its last frames' marginal; the same estimate of x's last frame.
  const std::vector<float> shorter(filled.end() - 4 * 3, filled.end());
  const std::vector<uint8_t> shorter_mask(mask.end() - 4 * 3, mask.end());
  CHECK(FillFromWindowGaussian(g, shorter, shorter_mask, GaussianScope::kOneSided)[3 * 3] ==
        Approx(clean[(T - 1) * 3]).margin(1e-3));
  // Every value of a motion the window covers: the bracketed one too (y = 2 x is observed there),
  // in a longer motion as one-sided alone.
  const std::vector<float> head(filled.begin(), filled.begin() + W * 3);
  const std::vector<uint8_t> head_mask(mask.begin(), mask.begin() + W * 3);
  const std::vector<float> every =
      FillFromWindowGaussian(g, head, head_mask, GaussianScope::kShortMotions);
  CHECK(every[4 * 3] == Approx(clean[4 * 3]).margin(1e-3));
  CHECK(every[1] == Approx(clean[1]).margin(2e-3));
  CHECK(FillFromWindowGaussian(g, filled, mask, GaussianScope::kShortMotions) == out);
  CHECK(ParseGaussianScope(GaussianScopeName(GaussianScope::kShortMotions)) ==
        GaussianScope::kShortMotions);
  CHECK_THROWS_WITH(ParseGaussianScope("all"),
                    Catch::Contains("expected one_sided or short_motions"));
  CHECK_THROWS_AS(
      FillFromWindowGaussian(g, filled, std::vector<uint8_t>(3, 0), GaussianScope::kOneSided),
      std::invalid_argument);
}

TEST_CASE("window Gaussian: each coordinate's first and last observed frame") {
  // [4 frames, 3 coordinates]: x seen in frames 1-2, y in every frame, z never.
  const std::vector<uint8_t> mask = {1, 0, 1, 0, 0, 1, 0, 0, 1, 1, 0, 1};
  const std::vector<ObservedSpan> s = ObservedSpans(mask, 3);
  REQUIRE(s.size() == 3);
  CHECK((s[0].first == 1 && s[0].last == 2));
  CHECK((s[1].first == 0 && s[1].last == 3));
  CHECK((s[2].first == 4 && s[2].last == 4));
}

TEST_CASE("window Gaussian: an extrapolation better than holding the last value") {
  // x alone (y and z missing too), its last 2 frames missing: the sinusoid's velocity carries on.
  const int W = 8;
  const WindowGaussian g = FitWindowGaussian(Clips(300, 40, 2), W, 3);
  double held = 0, gauss = 0;
  for (const std::vector<float>& clean : Clips(50, W, 3)) {
    std::vector<uint8_t> mask(clean.size(), 0);
    for (int t = 0; t < W; ++t) mask[t * 3 + 1] = mask[t * 3 + 2] = 1;
    std::vector<float> filled = clean;
    for (int t = W - 2; t < W; ++t) {
      mask[t * 3] = 1;
      filled[t * 3] = clean[(W - 3) * 3];  // held at the last observed value
    }
    const std::vector<float> out =
        FillFromWindowGaussian(g, filled, mask, GaussianScope::kOneSided);
    for (int t = W - 2; t < W; ++t) {
      held += std::pow(filled[t * 3] - clean[t * 3], 2);
      gauss += std::pow(out[t * 3] - clean[t * 3], 2);
    }
  }
  CHECK(gauss < 0.05 * held);
}

TEST_CASE("window Gaussian: stored as one .npy and read back; another shape is refused") {
  const WindowGaussian g = FitWindowGaussian(Clips(20, 12, 4), 4, 3);
  const std::string bytes = SerializeWindowGaussian(g);
  const WindowGaussian back = ParseWindowGaussian(bytes, 4, 3, g.windows, "w.npy");
  CHECK(back.windows == g.windows);
  REQUIRE(back.cov.size() == g.cov.size());
  for (size_t i = 0; i < g.cov.size(); ++i)
    CHECK(back.cov[i] == Approx(g.cov[i]).epsilon(1e-6).margin(1e-12));
  CHECK_THROWS_AS(ParseWindowGaussian(bytes, 5, 3, g.windows, "w.npy"), FormatError);
  CHECK_THROWS_WITH(ParseWindowGaussian(bytes, 5, 3, g.windows, "w.npy"),
                    Catch::Contains("w.npy: expected a window Gaussian of shape [16, 15]") &&
                        Catch::Contains("found [13, 12]"));
}

}  // namespace
}  // namespace motionfork
