// Posing a rig onto targets (pipeline/rig_solve.h): reachable targets are met, joints without a
// target below them keep their rotations, the root's translation follows.
#include "pipeline/rig_solve.h"

#include <algorithm>
#include <catch2/catch.hpp>

#include "io/bvh.h"
#include "io/bvh_rig.h"

using namespace motionfork;
using namespace motionfork::pipeline;

namespace {

// A root, a spine between it and the chest, two shoulders (clavicles) and arms with hands.
const char* kBvh = R"(HIERARCHY
ROOT Hips
{
  OFFSET 0 90 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0 10 1
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Chest
    {
      OFFSET 0 12 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT LeftShoulder
      {
        OFFSET 5 10 0
        CHANNELS 3 Zrotation Yrotation Xrotation
        JOINT LeftArm
        {
          OFFSET 12 0 0
          CHANNELS 3 Zrotation Yrotation Xrotation
          JOINT LeftHand
          {
            OFFSET 25 0 0
            CHANNELS 3 Zrotation Yrotation Xrotation
            End Site
            {
              OFFSET 8 0 0
            }
          }
        }
      }
      JOINT RightArm
      {
        OFFSET -17 10 0
        CHANNELS 3 Xrotation Zrotation Yrotation
        End Site
        {
          OFFSET -25 0 0
        }
      }
    }
  }
  JOINT LeftLeg
  {
    OFFSET 10 -5 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 -80 5
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.0333333
1 2 3 10 20 30 5 -5 15 2 3 4 1 1 1 40 -30 20 -10 10 5 10 60 5 10 0 0
30 -2 40 -20 10 170 5 25 -15 -3 8 -5 1 1 1 100 30 -20 -10 10 5 -20 -60 95 -10 20 5
)";

}  // namespace

// Targets from frame 1 at the named nodes; the rig solved from frame 0.
struct Solved {
  std::vector<double> targets, values;
  double before = 0, after = 0;
};
Solved SolveTowardFrame1(const BvhRig& rig, const std::vector<std::string>& names) {
  const BvhRigPose want = RigForwardKinematics(rig, rig.frame(1));
  std::vector<uint8_t> targeted(rig.nodes.size(), 0);
  for (size_t n = 0; n < rig.nodes.size(); ++n)
    targeted[n] = std::find(names.begin(), names.end(), rig.nodes[n].name) != names.end();
  const RigSolver solver(rig, targeted);
  Solved s{want.position, std::vector<double>(rig.frame(0), rig.frame(0) + rig.num_channels)};
  s.before = solver.Miss(s.targets, s.values.data());
  solver.Solve(s.targets, s.values.data());
  s.after = solver.Miss(s.targets, s.values.data());
  return s;
}

TEST_CASE("the rig solver meets reachable targets and holds what nothing steers") {
  BvhRig rig;
  ReadBvhText(kBvh, "rig.bvh", {}, &rig);
  // Every joint on the way targeted: each turn is told exactly, every target met.
  const Solved all = SolveTowardFrame1(rig, {"Hips", "Spine", "Chest", "LeftShoulder", "LeftArm",
                                             "LeftHand", "RightArm", "LeftLeg", "LeftLeg_End"});
  CHECK(all.before > 10);
  CHECK(all.after < 1e-6);
  // The hand has no target below it: its rotation is frame 0's.
  const BvhRig::Node* hand = nullptr;
  for (const BvhRig::Node& n : rig.nodes)
    if (n.name == "LeftHand") hand = &n;
  REQUIRE(hand);
  for (int c = 0; c < 3; ++c)
    CHECK(all.values[hand->first_channel + c] == rig.frame(0)[hand->first_channel + c]);
  // A spine, a shoulder and a hip joint no target names (as a model's joints leave a rig's extra
  // spine and clavicles): the solver turns them too, and comes within a few units (the joints
  // above them are told by directions, not by where those joints must be).
  const Solved some =
      SolveTowardFrame1(rig, {"Hips", "Chest", "LeftArm", "LeftHand", "RightArm", "LeftLeg_End"});
  INFO("miss " << some.before << " -> " << some.after);
  CHECK(some.after < some.before / 5);
  CHECK(some.after < 4);
}
