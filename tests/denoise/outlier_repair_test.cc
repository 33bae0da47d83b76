// Outliers repaired before the refiner: the joint-frames that fail the Hampel test are filled in
// again by linear interpolation in time, the rest left exactly as they were.
#include "denoise/outlier_repair.h"

#include <catch2/catch.hpp>
#include <cmath>

using namespace motionfork;

namespace {

// Two joints over `frames` frames: joint 0 moves on a straight line at about half a centimetre a
// frame, joint 1 swings slowly (a sine of 1 s period).
std::vector<float> TwoJoints(int frames) {
  std::vector<float> p;
  for (int t = 0; t < frames; ++t) {
    const double s = std::sin(2 * M_PI * t / 30.0);
    p.insert(p.end(), {0.005f * t, 1.0f, -0.0025f * t, float(0.1 * s), 0.5f, float(0.05 * s)});
  }
  return p;
}

}  // namespace

TEST_CASE("displaced joints are found and put back on their line; nothing else changes") {
  const std::vector<float> clean = TwoJoints(40);
  std::vector<float> noisy = clean;
  noisy[6 * 10 + 1] += 0.3f;  // joint 0, frame 10, y
  noisy[6 * 20 + 0] -= 0.3f;  // joint 0, frames 20 and 21, x: two frames in a row
  noisy[6 * 21 + 0] -= 0.35f;
  noisy[6 * 0 + 2] += 0.3f;  // joint 0, first frame, z: held at the first frame that passes
  const OutlierRepair repair{3, 4.0};
  const std::vector<uint8_t> flags = OutlierJoints(noisy, 2, repair);
  REQUIRE(flags.size() == 80);
  for (int t : {0, 10, 20, 21}) CHECK(flags[2 * t] == 1);
  int first = 0;
  while (flags[2 * first]) ++first;
  int repaired = -1, flagged = 0;
  const std::vector<float> out = RepairOutliers(noisy, 2, repair, &repaired);
  for (int t = 0; t < 40; ++t) {
    INFO("frame " << t);
    flagged += flags[2 * t];
    CHECK(flags[2 * t + 1] == 0);  // joint 1 swings smoothly: never an outlier
    for (int d = 0; d < 3; ++d) {
      const size_t i = 6 * t + d;
      if (t < first) {
        CHECK(out[i] == noisy[6 * first + d]);
      } else if (flags[2 * t]) {
        CHECK(out[i] == Approx(clean[i]).margin(1e-6));  // on the line again
      } else {
        CHECK(out[i] == noisy[i]);
      }
      CHECK(out[i + 3] == noisy[i + 3]);
    }
  }
  CHECK(repaired == flagged);
  CHECK(flagged <= 10);  // the displaced frames and at most their neighbours
}

TEST_CASE("a clean motion passes the repair unchanged, and no repair changes nothing") {
  const std::vector<float> clean = TwoJoints(90);
  int repaired = -1;
  CHECK(RepairOutliers(clean, 2, {3, 4.0}, &repaired) == clean);
  CHECK(repaired == 0);
  std::vector<float> noisy = clean;
  noisy[6 * 45] += 0.5f;
  CHECK(RepairOutliers(noisy, 2, OutlierRepair{}, &repaired) == noisy);
  CHECK(repaired == 0);
  CHECK(RepairOutliers(noisy, 2, {3, 4.0}, &repaired) != noisy);
  CHECK(repaired >= 1);
  CHECK(DescribeOutlierRepair(OutlierRepair{}) == "none");
  CHECK(DescribeOutlierRepair({3, 4.0}) == "Hampel test over +-3 frames at 4 deviations");
  CHECK_THROWS_WITH(OutlierJoints(std::vector<float>(7), 2, {3, 4.0}),
                    Catch::Contains("2 joints x 3"));
}

TEST_CASE("about the window's robust line, a small spike on a fast joint is found") {
  // One joint moving 5 cm a frame (and swinging a little), 3 cm off in frame 20: the Hampel test
  // on the raw values misses it (the window's spread is the motion), the test about the
  // Theil-Sen line finds it and only it.
  std::vector<float> clean;
  for (int t = 0; t < 40; ++t) {
    const float x = static_cast<float>(0.05 * t + 0.02 * std::sin(t / 5.0));
    clean.insert(clean.end(), {x, 1.0f, 0.0f});
  }
  std::vector<float> spiked = clean;
  spiked[3 * 20] += 0.03f;
  const OutlierRepair raw{3, 3.0}, trend{3, 3.0, true};
  CHECK(OutlierJoints(spiked, 1, raw) == std::vector<uint8_t>(40, 0));
  std::vector<uint8_t> expected(40, 0);
  expected[20] = 1;
  CHECK(OutlierJoints(spiked, 1, trend) == expected);
  CHECK(OutlierJoints(clean, 1, trend) == std::vector<uint8_t>(40, 0));
  const std::vector<float> out = RepairOutliers(spiked, 1, trend);
  CHECK(std::abs(out[3 * 20] - clean[3 * 20]) < 0.002);  // between its neighbours again
  CHECK(DescribeOutlierRepair(trend) ==
        "Hampel test about the Theil-Sen line over +-3 frames at 3 deviations");
}
