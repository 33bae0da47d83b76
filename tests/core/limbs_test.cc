#include "core/limbs.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "test_support.h"

using namespace motionfork;

TEST_CASE("positions -> limb directions and lengths -> positions round-trips to 1e-5 m") {
  const Motion m = testing::MakeWalkingMotion(60);
  const Limbs limbs = ToLimbs(m);
  REQUIRE(limbs.num_limbs == 16);
  for (int k = 0; k < 60 * 16; ++k) {
    const float* d = &limbs.directions[3 * k];
    CHECK(std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) == Approx(1.0).margin(1e-6));
  }
  const Motion back = FromLimbs(m.skeleton_ptr(), m.fps(), limbs);
  float worst = 0;
  for (size_t i = 0; i < m.positions().size(); ++i) {
    worst = std::max(worst, std::abs(back.positions()[i] - m.positions()[i]));
  }
  CHECK(worst < 1e-5f);
}

TEST_CASE("limbs re-target a motion to other bone lengths, keeping directions") {
  const Motion m = testing::MakeWalkingMotion(5);
  Limbs limbs = ToLimbs(m);
  for (float& l : limbs.lengths) l *= 1.5f;
  const Motion big = FromLimbs(m.skeleton_ptr(), m.fps(), limbs);
  const Limbs again = ToLimbs(big);
  for (size_t i = 0; i < again.directions.size(); ++i) {
    CHECK(again.directions[i] == Approx(limbs.directions[i]).margin(1e-5));
  }
}

TEST_CASE("a zero-length bone is reported with its frame and joint") {
  auto s = testing::MakeHumanoid();
  Motion m = testing::MakeWalkingMotion(3);
  std::vector<float> p = m.positions();
  const int j = s->Index("Hand_L"), parent = s->parent(j);
  for (int a = 0; a < 3; ++a) p[2 * 51 + 3 * j + a] = p[2 * 51 + 3 * parent + a];
  const Motion bad(s, 30, p);
  CHECK_THROWS_WITH(ToLimbs(bad), Catch::Contains("frame 2") && Catch::Contains("Hand_L"));
}
