// The classical filters as tuned baselines: the grid search picks the setting of least error on
// the motions it is given, heavier smoothing for heavier noise, whatever the threads.
#include "denoise/filter_tuning.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "denoise/denoise_metrics.h"

using namespace motionfork;
using Catch::Contains;

namespace {

using Sequences = std::vector<std::vector<float>>;

// Two joints moving smoothly (sines of a few Hz at 30 frames/s), one motion per phase.
Sequences CleanMotions(int count, int frames) {
  Sequences out;
  for (int c = 0; c < count; ++c) {
    std::vector<float> p;
    for (int t = 0; t < frames; ++t) {
      const double s = t / 30.0 + 0.37 * c;
      p.insert(p.end(), {float(0.3 * std::sin(2.1 * s)), float(0.2 * std::cos(3.3 * s)), 1.0f,
                         float(0.1 * std::sin(5.0 * s)), 0.5f, float(0.25 * std::cos(1.4 * s))});
    }
    out.push_back(p);
  }
  return out;
}

Sequences WithNoise(const Sequences& clean, double sigma, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  Sequences out = clean;
  for (auto& q : out)
    for (float& v : q) v += static_cast<float>(noise(rng));
  return out;
}

double Error(const FilterSetting& s, const Sequences& noisy, const Sequences& clean) {
  double sum = 0, frames = 0;
  for (size_t i = 0; i < noisy.size(); ++i) {
    const double n = noisy[i].size() / 6.0;
    sum += MeanJointError(ApplyFilter(s, noisy[i], 2, 30), clean[i]) * n;
    frames += n;
  }
  return sum / frames;
}

}  // namespace

TEST_CASE("every filter's grid runs and names its parameters") {
  const Sequences clean = CleanMotions(1, 50);
  for (FilterKind kind : {FilterKind::kGaussian, FilterKind::kSavitzkyGolay, FilterKind::kOneEuro,
                          FilterKind::kHampel}) {
    const std::vector<FilterSetting> grid = FilterGrid(kind);
    REQUIRE(grid.size() >= 10);
    for (const FilterSetting& s : grid) {
      INFO(DescribeFilter(s));
      CHECK(s.kind == kind);
      CHECK(DescribeFilter(s).rfind(FilterName(kind), 0) == 0);
      CHECK(ApplyFilter(s, clean[0], 2, 30).size() == clean[0].size());
    }
  }
  CHECK(DescribeFilter({FilterKind::kSavitzkyGolay, 5, 2}) ==
        "savitzky-golay (half window 5, order 2)");
  CHECK(DescribeFilter({FilterKind::kHampel, 3, 4}) == "hampel (half window 3, 4 deviations)");
}

TEST_CASE("against outliers the tuned Hampel filter beats the smoothers") {
  const Sequences clean = CleanMotions(4, 120);
  Sequences noisy = clean;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  for (auto& q : noisy)
    for (float& v : q)
      if (unit(rng) < 0.05) v += unit(rng) < 0.5 ? 0.3f : -0.3f;
  const TunedFilter hampel = TuneFilter(FilterKind::kHampel, noisy, clean, 2, 30);
  for (FilterKind kind :
       {FilterKind::kGaussian, FilterKind::kSavitzkyGolay, FilterKind::kOneEuro}) {
    INFO(FilterName(kind) << " against " << DescribeFilter(hampel.setting));
    CHECK(hampel.error_m < 0.5 * TuneFilter(kind, noisy, clean, 2, 30).error_m);
  }
  CHECK(hampel.setting.b > 0);  // a test, not the running median
}

TEST_CASE("tuning picks the grid's least error, heavier smoothing for heavier noise") {
  const Sequences clean = CleanMotions(4, 120);
  const Sequences light = WithNoise(clean, 0.005, 1), heavy = WithNoise(clean, 0.05, 2);
  for (FilterKind kind :
       {FilterKind::kGaussian, FilterKind::kSavitzkyGolay, FilterKind::kOneEuro}) {
    INFO(FilterName(kind));
    const TunedFilter a = TuneFilter(kind, light, clean, 2, 30);
    const TunedFilter b = TuneFilter(kind, heavy, clean, 2, 30, 2);
    // The minimum over the grid, recomputed here.
    for (const FilterSetting& s : FilterGrid(kind)) {
      CHECK(a.error_m <= Error(s, light, clean) + 1e-12);
      CHECK(b.error_m <= Error(s, heavy, clean) + 1e-12);
    }
    CHECK(a.error_m == Approx(Error(a.setting, light, clean)));
    // Filtering helps: less error than the noise left alone.
    CHECK(b.error_m < 0.7 * MeanJointError(heavy[0], clean[0]));
    // Heavier noise, heavier smoothing: a wider Gaussian or window, a lower cutoff.
    if (kind == FilterKind::kOneEuro) {
      CHECK(b.setting.a <= a.setting.a);
    } else {
      CHECK(b.setting.a >= a.setting.a);
    }
    CHECK(DescribeFilter(a.setting) != DescribeFilter(b.setting));
  }
}

TEST_CASE("tuning gives the same setting on any number of threads") {
  const Sequences clean = CleanMotions(3, 90);
  const Sequences noisy = WithNoise(clean, 0.02, 3);
  const TunedFilter one = TuneFilter(FilterKind::kSavitzkyGolay, noisy, clean, 2, 30, 1);
  const TunedFilter two = TuneFilter(FilterKind::kSavitzkyGolay, noisy, clean, 2, 30, 2);
  CHECK(DescribeFilter(one.setting) == DescribeFilter(two.setting));
  CHECK(one.error_m == two.error_m);
}

TEST_CASE("tuning refuses no motions and motions of different sizes") {
  const Sequences clean = CleanMotions(2, 30);
  CHECK_THROWS_WITH(TuneFilter(FilterKind::kGaussian, {}, {}, 2, 30), Contains("at least one"));
  Sequences short_one = clean;
  short_one[1].resize(short_one[1].size() - 6);
  CHECK_THROWS_WITH(TuneFilter(FilterKind::kGaussian, short_one, clean, 2, 30),
                    Contains("motion 1 has"));
}
