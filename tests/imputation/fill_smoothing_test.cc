#include "imputation/fill_smoothing.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace motionfork {
namespace {

// Two coordinates over T frames: a straight line in time and a parabola.
std::vector<float> Lines(int T) {
  std::vector<float> v(2 * static_cast<size_t>(T));
  for (int t = 0; t < T; ++t) {
    v[2 * t] = 0.1f + 0.01f * t;
    v[2 * t + 1] = 0.002f * t * t;
  }
  return v;
}

TEST_CASE("fill smoothing: a bracketed gap of a straight line is restored from a jittery fill") {
  const int T = 20;
  const std::vector<float> clean = Lines(T);
  std::vector<uint8_t> mask(clean.size(), 0);
  std::vector<float> filled = clean;
  for (int t = 6; t < 12; ++t) {
    mask[2 * t] = 1;
    filled[2 * t] += (t % 2 ? 0.02f : -0.02f);  // a jittery fill
  }
  const std::vector<float> out = SmoothFilledValues(filled, mask, 2, {1e4, 0});
  for (size_t i = 0; i < out.size(); ++i) {
    if (!mask[i]) REQUIRE(out[i] == filled[i]);  // observed values stay exactly
    if (mask[i]) CHECK(out[i] == Approx(clean[i]).margin(2e-5));
  }
  // lambda 0 keeps the fill as it is; a small lambda moves it only a little.
  CHECK(SmoothFilledValues(filled, mask, 2, {0, 0}) == filled);
  const std::vector<float> light = SmoothFilledValues(filled, mask, 2, {0.01, 0});
  for (int t = 6; t < 12; ++t) {
    CHECK(std::abs(light[2 * t] - filled[2 * t]) < 0.01f);
    CHECK(std::abs(light[2 * t] - filled[2 * t]) > 0.0f);
  }
}

TEST_CASE("fill smoothing: values observed on one side only go on with the motion's velocity") {
  const int T = 15;
  const std::vector<float> clean = Lines(T);
  std::vector<uint8_t> mask(clean.size(), 0);
  std::vector<float> held = clean;  // the last 4 frames held at the last observed value
  for (int t = 11; t < T; ++t) {
    mask[2 * t] = 1;
    held[2 * t] = clean[2 * 10];
  }
  // Only the one-sided lambda acts here.
  CHECK(SmoothFilledValues(held, mask, 2, {1e4, 0}) == held);
  const std::vector<float> out = SmoothFilledValues(held, mask, 2, {0, 1e6});
  for (int t = 11; t < T; ++t) CHECK(out[2 * t] == Approx(clean[2 * t]).margin(1e-4));
  // A moderate lambda lands between holding and going on.
  const std::vector<float> some = SmoothFilledValues(held, mask, 2, {0, 3});
  CHECK(some[2 * (T - 1)] > held[2 * (T - 1)]);
  CHECK(some[2 * (T - 1)] < clean[2 * (T - 1)]);
}

TEST_CASE("fill smoothing: coordinates never observed stay as filled; bad input is refused") {
  const int T = 10;
  std::vector<float> v = Lines(T);
  std::vector<uint8_t> mask(v.size(), 0);
  for (int t = 0; t < T; ++t) {
    mask[2 * t + 1] = 1;  // the parabola never observed
    v[2 * t + 1] = (t % 2) ? 0.5f : -0.5f;
  }
  CHECK(SmoothFilledValues(v, mask, 2, {100, 100}) == v);
  CHECK_THROWS_AS(SmoothFilledValues(v, mask, 3, {1, 1}), std::invalid_argument);
  CHECK_THROWS_WITH(SmoothFilledValues(v, mask, 2, {-1, 0}),
                    Catch::Contains("bracketed expected a finite lambda >= 0"));
  CHECK_THROWS_WITH(SmoothFilledValues(v, mask, 2, {0, NAN}),
                    Catch::Contains("one_sided expected a finite lambda >= 0"));
  std::vector<uint8_t> short_mask(v.size() - 2, 0);
  CHECK_THROWS_AS(SmoothFilledValues(v, short_mask, 2, {1, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace motionfork
