// The plausibility gate on a synthetic walk (tests/test_support.h): as made, no doubt; in
// millimetres, turned to Z up, or with its sides exchanged, the doubt names what is off.
#include "pipeline/history_check.h"

#include <catch2/catch.hpp>

#include "config/rig_config.h"
#include "rig/joint_mapping.h"
#include "test_support.h"
#include "validity/pose_validator.h"

using namespace motionfork;
using namespace motionfork::pipeline;

namespace {

// Doubts of a history under a judge with no constraints and no prior (only the body is measured).
std::vector<std::string> Doubts(const Motion& m) {
  const PoseValidator none(m.skeleton_ptr(), m.fps(), "", "");
  const std::vector<std::string> roles =
      RolesOfSkeleton(m.skeleton(), LoadRigConventions(MOTIONFORK_CONFIG_DIR)).roles;
  return CheckHistory(m, none.Score(m.positions().data(), m.num_frames()), none, nullptr, roles,
                      "y")
      .doubts;
}

Motion Transformed(const Motion& m, float scale, bool z_up, bool exchange_sides) {
  std::vector<float> p = m.positions();
  const Skeleton& s = m.skeleton();
  for (int t = 0; t < m.num_frames(); ++t) {
    for (int j = 0; j < s.num_joints(); ++j) {
      const int from = exchange_sides ? s.Mirror(j) : j;
      const float* a = m.at(t, from);
      float* b = p.data() + (static_cast<size_t>(t) * s.num_joints() + j) * 3;
      b[0] = scale * a[0];
      b[1] = scale * (z_up ? -a[2] : a[1]);
      b[2] = scale * (z_up ? a[1] : a[2]);
    }
  }
  return Motion(m.skeleton_ptr(), m.fps(), std::move(p));
}

bool AnyStartsWith(const std::vector<std::string>& v, const std::string& start) {
  for (const std::string& s : v)
    if (s.rfind(start, 0) == 0) return true;
  return false;
}

}  // namespace

TEST_CASE("the gate finds no doubt in a walk and names the scale, axis or sides that are off") {
  const Motion walk = testing::MakeWalkingMotion(15);
  CHECK(Doubts(walk).empty());
  const std::vector<std::string> mm = Doubts(Transformed(walk, 1000, false, false));
  REQUIRE(mm.size() == 1);
  CHECK(mm[0].rfind("scale: ", 0) == 0);
  CHECK(mm[0].find("millimetres") != std::string::npos);
  CHECK(AnyStartsWith(Doubts(Transformed(walk, 1, true, false)), "axis: "));
  CHECK(AnyStartsWith(Doubts(Transformed(walk, 1, false, true)), "left/right: "));
  CHECK(AnyStartsWith(Doubts(Transformed(walk, 0.0001f, false, false)), "scale: "));
}

TEST_CASE("the gate judges a skeleton no rig convention names without its body frame") {
  const Motion walk = testing::MakeWalkingMotion(15);
  std::vector<float> mm = walk.positions();
  for (float& v : mm) v *= 1000;
  const Motion far(walk.skeleton_ptr(), walk.fps(), mm);
  const PoseValidator none(far.skeleton_ptr(), far.fps(), "", "");
  // No roles: size, up axis and left/right are not judged (no throw, no doubt).
  CHECK(CheckHistory(far, none.Score(mm.data(), 15), none, nullptr, {}, "y").doubts.empty());
}

TEST_CASE("the futures of a doubted history are not valid, and say so") {
  Prediction p;
  p.samples.resize(2);
  p.samples[1].violating_frames = 3;
  p.samples[1].valid = false;
  p.history_check = HistoryCheck{};
  MarkFuturesOfDoubtedHistory(&p);
  CHECK(p.samples[0].valid);  // no doubt: nothing changes
  p.history_check->doubts = {"scale: ..."};
  MarkFuturesOfDoubtedHistory(&p);
  CHECK_FALSE(p.samples[0].valid);
  CHECK(p.samples[0].Failed() == std::vector<std::string>{"history"});
  CHECK(p.samples[1].Failed() == std::vector<std::string>{"angle_ranges", "history"});
}
