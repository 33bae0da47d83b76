// A BVH file's own rig (io/bvh_rig.h): its text written back reads as the same motion, Euler angles
// in every channel order compose the rotation they were taken from, and (pipeline/rig_solve.h is
// tested in tests/pipeline) forward kinematics agrees with the reader's.
#include "io/bvh_rig.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "io/bvh.h"

using namespace motionfork;

namespace {

// A small rig: a root with 6 channels, a spine, two arms (one ZYX, one XZY), an End Site.
const char* kBvh = R"(HIERARCHY
ROOT Hips
{
  OFFSET 0 90 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0 20 1
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT LeftArm
    {
      OFFSET 15 10 0
      CHANNELS 3 Zrotation Yrotation Xrotation
      End Site
      {
        OFFSET 25 0 0
      }
    }
    JOINT RightArm
    {
      OFFSET -15 10 0
      CHANNELS 3 Xrotation Zrotation Yrotation
      End Site
      {
        OFFSET -25 0 0
      }
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.0166667
1 2 3 10 20 30 5 -5 15 40 -30 20 -10 60 5
-1 0.5 3 -20 10 170 5 5 -15 100 30 -20 10 -60 95
)";

}  // namespace

TEST_CASE("a BVH rig's text reads back to the same positions, frame rate and channels") {
  BvhRig rig;
  BvhOptions o;
  o.include_end_sites = true;
  const Motion m = ReadBvhText(kBvh, "rig.bvh", o, &rig);
  REQUIRE(rig.nodes.size() == 6);
  CHECK(rig.num_channels == 15);
  CHECK(rig.num_frames() == 2);
  CHECK(rig.fps == Approx(60));
  CHECK(rig.nodes[3].end_site);
  CHECK(rig.nodes[3].name == "LeftArm_End");
  BvhRig again;
  const Motion back =
      ReadBvhText(BvhRigText(rig, rig.values, rig.frame_time), "again.bvh", o, &again);
  REQUIRE(back.positions().size() == m.positions().size());
  for (size_t i = 0; i < m.positions().size(); ++i)
    CHECK(back.positions()[i] == Approx(m.positions()[i]).margin(1e-7));
  CHECK(again.fps == Approx(60));
  for (size_t n = 0; n < rig.nodes.size(); ++n)
    CHECK(again.nodes[n].channels == rig.nodes[n].channels);
  // Forward kinematics of the rig: the reader's positions (file units; read in metres here).
  for (int t = 0; t < 2; ++t) {
    const BvhRigPose pose = RigForwardKinematics(rig, rig.frame(t));
    for (int n = 0; n < 6; ++n)
      for (int a = 0; a < 3; ++a) CHECK(pose.p(n)[a] * 0.01 == Approx(m.at(t, n)[a]).margin(1e-6));
  }
}

TEST_CASE("Euler angles in any channel order compose the rotation, nearest the previous ones") {
  const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-179, 179), tilt(-85, 85);
  for (const auto& order : orders) {
    BvhRig::Node node;
    node.channels = {order[0] + 3, order[1] + 3, order[2] + 3};
    for (int trial = 0; trial < 50; ++trial) {
      double v[3] = {angle(rng), tilt(rng), angle(rng)};
      double r[9];
      RigLocalRotation(node, v, r);
      double near[3] = {v[0] + 720, v[1], v[2] - 360};  // the same angles two turns away
      REQUIRE(SetRigLocalRotation(node, r, near));
      CHECK(near[0] == Approx(v[0] + 720).margin(1e-6));
      CHECK(near[1] == Approx(v[1]).margin(1e-6));
      CHECK(near[2] == Approx(v[2] - 360).margin(1e-6));
      double r2[9];
      RigLocalRotation(node, near, r2);
      for (int q = 0; q < 9; ++q) CHECK(r2[q] == Approx(r[q]).margin(1e-9));
    }
  }
  // Gimbal lock (the middle angle at +-90 degrees): only a sum of the outer two is told; the
  // angles found compose the same rotation.
  for (const auto& order : orders) {
    BvhRig::Node node;
    node.channels = {order[0] + 3, order[1] + 3, order[2] + 3};
    for (const double middle : {90.0, -90.0, 89.9999999}) {
      const double v[3] = {30, middle, -50};
      double r[9];
      RigLocalRotation(node, v, r);
      double got[3] = {10, 0, -40};
      REQUIRE(SetRigLocalRotation(node, r, got));
      double r2[9];
      RigLocalRotation(node, got, r2);
      for (int q = 0; q < 9; ++q) CHECK(r2[q] == Approx(r[q]).margin(1e-6));
    }
  }
  BvhRig::Node two;
  two.channels = {3, 4};
  double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, v[2] = {0, 0};
  CHECK_FALSE(SetRigLocalRotation(two, r, v));
}
