#include "core/motion.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "core/joint_selection.h"
#include "core/resample.h"
#include "test_support.h"

using namespace motionfork;

TEST_CASE("motion validates its sizes and values") {
  auto s = testing::MakeHumanoid();
  CHECK_THROWS_WITH(Motion(s, 30, std::vector<float>(50)), Catch::Contains("multiple of 51"));
  CHECK_THROWS_WITH(Motion(s, 0, std::vector<float>(51)), Catch::Contains("frame rate"));
  std::vector<float> p(102, 0.0f);
  p[51 + 3 * 5 + 1] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(Motion(s, 30, p), Catch::Contains("frame 1") && Catch::Contains("LowerLeg_L"));
}

TEST_CASE("root-relative poses put the root at the origin and drop it from pose vectors") {
  const Motion m = testing::MakeWalkingMotion(10);
  const Motion r = RootRelative(m);
  const auto v = PoseVectorsWithoutRoot(m);
  REQUIRE(v.size() == 10u * 48);
  for (int t = 0; t < 10; ++t) {
    for (int a = 0; a < 3; ++a) CHECK(r.at(t, 0)[a] == 0.0f);
    for (int j = 1; j < 17; ++j) {
      for (int a = 0; a < 3; ++a) {
        CHECK(v[t * 48 + (j - 1) * 3 + a] == Approx(m.at(t, j)[a] - m.at(t, 0)[a]).margin(1e-6));
        CHECK(r.at(t, j)[a] == Approx(m.at(t, j)[a] - m.at(t, 0)[a]).margin(1e-6));
      }
    }
  }
}

TEST_CASE("joint selection keeps named joints and re-parents to the nearest kept ancestor") {
  auto s = testing::MakeHumanoid();
  JointSelectionSpec spec;
  spec.name = "small";
  spec.keep = {"Hips", "Chest", "Hand_L", "Head"};
  const JointSelection sel = SelectJoints(*s, spec);
  CHECK(sel.skeleton.parents() == std::vector<int>{-1, 0, 1, 1});
  CHECK(sel.source_index == std::vector<int>{0, 8, 13, 10});
  spec.reparent = {{"Head", "Hips"}};
  CHECK(SelectJoints(*s, spec).skeleton.parents() == std::vector<int>{-1, 0, 1, 0});

  const Motion m = testing::MakeWalkingMotion(5);
  const Motion small = ApplySelection(m, sel);
  for (int t = 0; t < 5; ++t) {
    for (int j = 0; j < 4; ++j) {
      for (int a = 0; a < 3; ++a) CHECK(small.at(t, j)[a] == m.at(t, sel.source_index[j])[a]);
    }
  }
  spec.keep = {"Hips", "Head", "Neck"};
  spec.reparent.clear();
  CHECK_THROWS_WITH(SelectJoints(*s, spec), Catch::Contains("'Neck'"));
  spec.keep = {"Hips", "Tail"};
  CHECK_THROWS_WITH(SelectJoints(*s, spec), Catch::Contains("no joint 'Tail'"));
}

TEST_CASE("resampling by an integer ratio keeps every k-th frame") {
  const Motion m = testing::MakeWalkingMotion(121, 120.0);
  const Motion r = Resample(m, 30.0);
  REQUIRE(r.num_frames() == 31);
  CHECK(r.fps() == 30.0);
  for (int t = 0; t < r.num_frames(); ++t) {
    for (int k = 0; k < 51; ++k) CHECK(r.frame(t)[k] == Approx(m.frame(4 * t)[k]).margin(1e-6));
  }
  const Motion h = Resample(testing::MakeWalkingMotion(100, 50.0), 25.0);
  CHECK(h.num_frames() == 50);
}

TEST_CASE("resampling to a non-integer ratio interpolates linearly") {
  // Positions linear in time are reproduced exactly by linear interpolation.
  auto s = testing::MakeHumanoid();
  std::vector<float> p(30 * 51);
  for (int t = 0; t < 30; ++t)
    for (int k = 0; k < 51; ++k) p[t * 51 + k] = 0.01f * k + 0.5f * t / 30.0f;
  const Motion m(s, 30.0, p);
  const Motion r = Resample(m, 25.0);
  CHECK(r.num_frames() == 25);  // 29 / 1.2 = 24.17 -> frames 0..24
  for (int i = 0; i < r.num_frames(); ++i) {
    const double time = i / 25.0;
    for (int k = 0; k < 51; ++k) CHECK(r.frame(i)[k] == Approx(0.01 * k + 0.5 * time).margin(1e-5));
  }
  CHECK_THROWS(Resample(m, 0));
}

TEST_CASE("slowing a motion down stretches it in time: speeds / factor, accelerations / factor^2") {
  // One joint on a parabola x = t^2 (frames): slowed 2x, x(i) = (i / 2)^2 at whole source frames,
  // and the second difference falls from 2 to 2 / 4 between them.
  std::vector<float> p;
  for (int t = 0; t < 11; ++t) p.insert(p.end(), {static_cast<float>(t * t), 1.0f, -2.0f});
  const std::vector<float> slow = SlowDown(p, 1, 2.0);
  REQUIRE(slow.size() == 21 * 3);  // frames 0..20 at source times 0, 0.5, ..., 10
  for (int i = 0; i <= 20; i += 2) CHECK(slow[i * 3] == Approx((i / 2.0) * (i / 2.0)));
  CHECK(slow[3 * 3] == Approx((1 + 4) / 2.0));  // halfway between frames 1 and 2
  CHECK(slow[10 * 3 + 1] == 1.0f);
  CHECK(slow[10 * 3 + 2] == -2.0f);
  CHECK(slow[4 * 3] - 2 * slow[6 * 3] + slow[8 * 3] == Approx(2.0));  // = 2 source frames apart
  CHECK(SlowDown(p, 1, 1.0) == p);
  CHECK_THROWS_WITH(SlowDown(p, 1, 0), Catch::Contains("factor > 0"));
  CHECK_THROWS_WITH(SlowDown(p, 2, 2.0), Catch::Contains("[T, 2, 3]"));
}
