// core/heading.h: the ground plane, a pose's heading, turning about the up axis.
#include "core/heading.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "test_support.h"

using namespace motionfork;

namespace {

// A 17-joint humanoid pose from a walking motion, frame t.
std::vector<float> Pose(const Motion& m, int t) {
  return std::vector<float>(m.frame(t), m.frame(t) + m.num_joints() * 3);
}

}  // namespace

TEST_CASE("up axes parse and give their ground plane") {
  CHECK(ParseUp("y").axis == 1);
  CHECK(ParseUp("-Z").axis == 2);
  CHECK(ParseUp("-Z").sign == -1);
  CHECK(ParseUp("+x").sign == 1);
  CHECK_THROWS_WITH(ParseUp("w"), Catch::Contains("expected auto, y, z"));
  CHECK(GroundAxes({1, 1}) == std::make_pair(2, 0));
  CHECK(GroundAxes({2, -1}) == std::make_pair(0, 1));
  CHECK_THROWS_WITH(GroundAxes({3, 1}), Catch::Contains("expected axis 0-2"));
}

TEST_CASE("the heading joints are the hips hanging on the root") {
  const auto skel = testing::MakeHumanoid();
  const auto j = FindHeadingJoints(*skel);
  REQUIRE(j);
  CHECK(skel->joint_name(j->left) == "UpperLeg_L");
  CHECK(skel->joint_name(j->right) == "UpperLeg_R");
  CHECK_FALSE(FindHeadingJoints(Skeleton::Anonymous(5)));
  // The generator's nodes leave the root out.
  const HeadingJoints nodes = HeadingNodes(*skel);
  CHECK(nodes.left == j->left - 1);
  CHECK(nodes.right == j->right - 1);
  CHECK_THROWS_WITH(HeadingNodes(Skeleton::Anonymous(5)), Catch::Contains("no left/right joint"));
}

TEST_CASE("turning a pose about up turns its heading by the same angle and keeps heights") {
  const Motion m = testing::MakeWalkingMotion(20);
  const HeadingJoints j = *FindHeadingJoints(m.skeleton());
  for (const UpAxis up : {UpAxis{1, 1}, UpAxis{2, -1}, UpAxis{0, 1}}) {
    std::vector<float> pose = Pose(m, 7);
    const double before = HeadingAngle(pose.data(), j, up);
    REQUIRE_FALSE(std::isnan(before));
    for (double turn : {0.3, -2.0, 3.0}) {
      std::vector<float> turned = pose;
      RotateAboutUp(turned.data(), 17, turn, up);
      const double after = HeadingAngle(turned.data(), j, up);
      CHECK(std::remainder(after - before - turn, 2 * M_PI) == Approx(0).margin(1e-5));
      for (int k = 0; k < 17; ++k) CHECK(turned[3 * k + up.axis] == pose[3 * k + up.axis]);
      RotateAboutUp(turned.data(), 17, -turn, up);  // and back
      for (size_t i = 0; i < pose.size(); ++i) CHECK(turned[i] == Approx(pose[i]).margin(1e-6));
    }
  }
}

TEST_CASE("a window's heading falls back to its frames' sum when the last frame tells none") {
  const Motion m = testing::MakeWalkingMotion(6);
  const HeadingJoints j = *FindHeadingJoints(m.skeleton());
  const UpAxis up{1, 1};
  std::vector<float> window(m.positions().begin(), m.positions().end());
  const double own = WindowHeading(window.data(), 6, 17, 5, j, up);
  CHECK(own == Approx(HeadingAngle(window.data() + 5 * 51, j, up)));
  // The last frame's hips one above the other: no heading there.
  float* last = window.data() + 5 * 51;
  for (int a : {0, 2}) last[3 * j.left + a] = last[3 * j.right + a];
  CHECK(std::isnan(HeadingAngle(last, j, up)));
  const double fallback = WindowHeading(window.data(), 6, 17, 5, j, up);
  CHECK_FALSE(std::isnan(fallback));
  CHECK(std::abs(std::remainder(fallback - own, 2 * M_PI)) < 0.3);
  CHECK_THROWS_WITH(WindowHeading(window.data(), 6, 17, 6, j, up), Catch::Contains("outside 0-5"));
}
