// The classical smoothing filters a denoiser is measured against (no LibTorch).
#include "denoise/motion_filters.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "denoise/denoise_metrics.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;

namespace {

// One joint whose x follows f(t), y = 2 f(t), z = -f(t).
std::vector<float> Track(int frames, double (*f)(double)) {
  std::vector<float> p;
  for (int t = 0; t < frames; ++t) {
    const double v = f(t);
    p.insert(p.end(), {float(v), float(2 * v), float(-v)});
  }
  return p;
}

double Quadratic(double t) { return 0.01 * t * t - 0.3 * t + 1.0; }
double SlowQuadratic(double t) { return 0.001 * t * t - 0.03 * t + 1.0; }  // turns at frame 15

}  // namespace

TEST_CASE("Savitzky-Golay keeps a polynomial of its degree exactly, also at the ends") {
  const std::vector<float> q = Track(40, Quadratic);
  for (int h : {1, 3, 7}) {
    const std::vector<float> out = SavitzkyGolay(q, 1, h, 2);
    for (size_t i = 0; i < q.size(); ++i) CHECK(out[i] == Approx(q[i]).margin(1e-4));
  }
  // Degree 1 cannot follow the curve; degree 0 in the middle is the moving average.
  CHECK(MeanJointError(SavitzkyGolay(q, 1, 5, 1), q) > 1e-3);
  const std::vector<float> avg = SavitzkyGolay(q, 1, 2, 0);
  double mean = 0;
  for (int t = 8; t <= 12; ++t) mean += q[t * 3] / 5.0;
  CHECK(avg[10 * 3] == Approx(mean).margin(1e-5));
}

TEST_CASE("Savitzky-Golay and the one-euro filter remove noise from a real motion") {
  const Motion clean = testing::MakeWalkingMotion(120);
  std::vector<float> noisy = clean.positions();
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.03f);
  for (float& v : noisy) v += noise(rng);
  const int J = clean.num_joints();
  const double before = MeanJointError(noisy, clean.positions());
  CHECK(MeanJointError(SavitzkyGolay(noisy, J, 4, 2), clean.positions()) < 0.7 * before);
  // The one-euro filter needs its two parameters tuned (a walking body lags behind a low cutoff):
  // the best of a small grid.
  double best = 1e9;
  for (double min_cutoff : {0.5, 1.0, 2.0, 4.0, 8.0})
    for (double beta : {0.0, 0.5, 2.0, 8.0})
      best = std::min(
          best, MeanJointError(OneEuroFilter(noisy, J, 30.0, min_cutoff, beta), clean.positions()));
  INFO("noisy " << before << ", best one-euro " << best);
  CHECK(best < 0.8 * before);
}

TEST_CASE("the one-euro filter: constant input kept, a fast cutoff passes the input through") {
  std::vector<float> still(3 * 50, 0.25f);
  CHECK(OneEuroFilter(still, 1, 30.0, 1.0, 0.5) == still);
  const std::vector<float> q = Track(60, Quadratic);
  // The first frame is kept; a high cutoff follows the input closely, a low one lags.
  const std::vector<float> fast = OneEuroFilter(q, 1, 30.0, 1000.0, 0.0);
  const std::vector<float> slow = OneEuroFilter(q, 1, 30.0, 0.05, 0.0);
  CHECK(fast[0] == q[0]);
  CHECK(MeanJointError(fast, q) < 1e-2);
  CHECK(MeanJointError(slow, q) > 0.1);
  // Speed raises the cutoff: with beta > 0 the lag on the moving curve is smaller.
  CHECK(MeanJointError(OneEuroFilter(q, 1, 30.0, 0.05, 1.0), q) < MeanJointError(slow, q));
}

TEST_CASE("the filters refuse bad parameters and sizes, naming them") {
  const std::vector<float> q = Track(10, Quadratic);
  CHECK_THROWS_WITH(SavitzkyGolay(q, 1, 0, 2), Contains("half_window"));
  CHECK_THROWS_WITH(SavitzkyGolay(std::vector<float>(7), 1, 2, 2), Contains("joints x 3"));
  CHECK_THROWS_WITH(OneEuroFilter(q, 1, 0.0, 1.0, 0.0), Contains("fps"));
  CHECK_THROWS_WITH(OneEuroFilter(q, 1, 30.0, 1.0, -1.0), Contains("beta"));
  CHECK_THROWS_WITH(HampelFilter(q, 1, 0, 3.0), Contains("half_window"));
  CHECK_THROWS_WITH(HampelFilter(q, 1, 2, -1.0), Contains("n_sigma"));
  CHECK_THROWS_WITH(HampelFilter(std::vector<float>(7), 1, 2, 3.0), Contains("joints x 3"));
}

TEST_CASE("the Hampel filter replaces spikes by their window's median and keeps the rest") {
  // A slow quadratic (falling, turning at frame 15) with spikes of 30 cm on x at frames 7 and 15.
  const std::vector<float> q = Track(60, SlowQuadratic);
  std::vector<float> spiked = q;
  spiked[3 * 7] += 0.3f;
  spiked[3 * 15] -= 0.3f;
  const std::vector<float> out = HampelFilter(spiked, 1, 3, 3.0);
  std::vector<float> medians;
  const std::vector<uint8_t> flags = HampelOutliers(spiked, 1, 3, 3.0, &medians);
  for (size_t i = 0; i < q.size(); ++i) {
    INFO("value " << i);
    const bool spike = i == 3 * 7 || i == 3 * 15;
    CHECK(flags[i] == (spike ? 1 : 0));
    // A spike becomes its median: one of its neighbours' values, within a frame's motion of it.
    CHECK(out[i] == (spike ? medians[i] : spiked[i]));
  }
  CHECK(std::abs(out[3 * 7] - q[3 * 7]) < 0.04);
  CHECK(std::abs(out[3 * 15] - q[3 * 15]) < 0.01);
  // The running median (0 deviations) of a monotone stretch is the stretch itself.
  const std::vector<float> median = HampelFilter(q, 1, 2, 0.0);
  for (int t = 2; t < 12; ++t) CHECK(median[3 * t] == q[3 * t]);
}
