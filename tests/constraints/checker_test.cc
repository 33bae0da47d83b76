// The angle checker: invariances, mirror symmetry, impossible poses, degenerate vectors, summary.
#include <catch2/catch.hpp>
#include <cmath>

#include "fixtures.h"
#include "test_support.h"

using namespace motionfork;
using namespace motionfork::testing;

namespace {

// The three shipped sets on their own skeletons, with a base pose for random poses around it.
struct Case {
  std::string name;
  std::shared_ptr<const Skeleton> skeleton;
  Pose base;
};
std::vector<Case> ShippedCases() {
  std::vector<Case> out;
  const auto h36m = ShippedSkeleton("h36m").skeleton;
  const auto humaneva = ShippedSkeleton("humaneva").skeleton;
  const auto bandai = ShippedSkeleton("bandai").skeleton;
  out.push_back({"h36m", h36m, H36mNeutral(*h36m)});
  out.push_back({"humaneva", humaneva, HumanEvaNeutral(*humaneva)});
  // Same layout as H36M's: the neutral pose by index.
  out.push_back({"bandai", bandai, H36mNeutral(*h36m)});
  return out;
}

std::vector<float> Angles(const ConstraintSet& set, const std::vector<float>& poses, int n) {
  std::vector<float> a(static_cast<size_t>(n) * set.num_constraints());
  AngleChecker(set).Run(poses.data(), n, a.data(), nullptr);
  return a;
}

}  // namespace

TEST_CASE("angles do not change under global rotation, translation and uniform scaling") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  std::uniform_real_distribution<float> log_scale(std::log(0.05f), std::log(20.0f));
  for (const Case& k : ShippedCases()) {
    const ConstraintSet set = ShippedSet(k.name, *k.skeleton);
    const int n = 500;
    const std::vector<float> poses = RandomPoses(k.base, n, 0.08f, 3);
    const std::vector<float> ref = Angles(set, poses, n);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Quaternionf q = Eigen::Quaternionf(u(rng), u(rng), u(rng), u(rng)).normalized();
      const Eigen::Vector3f shift(10 * u(rng), 10 * u(rng), 10 * u(rng));
      const float scale = std::exp(log_scale(rng));
      std::vector<float> moved(poses.size());
      for (size_t i = 0; i < poses.size(); i += 3) {
        const Eigen::Vector3f x(poses[i], poses[i + 1], poses[i + 2]);
        Eigen::Map<Eigen::Vector3f>(moved.data() + i) = scale * (q * x) + shift;
      }
      const std::vector<float> got = Angles(set, moved, n);
      float worst = 0;
      for (size_t i = 0; i < ref.size(); ++i) worst = std::max(worst, std::abs(got[i] - ref[i]));
      INFO(k.name << " trial " << trial << " scale " << scale);
      // float acos near 0 and 180 degrees resolves ~0.03 degrees; elsewhere far better.
      CHECK(worst < 0.1f);
    }
  }
}

TEST_CASE("a pose and its left/right mirror give swapped per-side angles") {
  for (const Case& k : ShippedCases()) {
    const ConstraintSet set = ShippedSet(k.name, *k.skeleton);
    const int n = 300;
    const std::vector<float> poses = RandomPoses(k.base, n, 0.08f, 5);
    std::vector<float> mirrored;
    const size_t stride = k.base.size();
    for (int i = 0; i < n; ++i) {
      const Pose p(poses.begin() + i * stride, poses.begin() + (i + 1) * stride);
      const Pose m = Mirrored(*k.skeleton, p);
      mirrored.insert(mirrored.end(), m.begin(), m.end());
    }
    const std::vector<float> a = Angles(set, poses, n);
    const std::vector<float> b = Angles(set, mirrored, n);
    const int C = set.num_constraints();
    int per_side = 0;
    for (int c = 0; c < C; ++c) {
      const Constraint& con = set.constraint(c);
      per_side += con.side != Side::kNone;
      if (con.side != Side::kNone) {
        REQUIRE(set.constraint(con.mirror).base_name == con.base_name);
        REQUIRE(set.constraint(con.mirror).side != con.side);
      }
      float worst = 0;
      for (int i = 0; i < n; ++i) {
        worst = std::max(worst, std::abs(b[i * C + c] - a[i * C + con.mirror]));
      }
      INFO(k.name << ": " << con.name << " vs mirror " << set.constraint(con.mirror).name);
      CHECK(worst < 0.1f);
    }
    CHECK(per_side >= 6);
  }
}

TEST_CASE("a neutral standing pose fires no constraint") {
  const auto h36m = ShippedSkeleton("h36m").skeleton;
  const auto humaneva = ShippedSkeleton("humaneva").skeleton;
  for (const auto& [set_name, skeleton, pose] :
       {std::make_tuple("h36m", h36m, H36mNeutral(*h36m)),
        std::make_tuple("humaneva", humaneva, HumanEvaNeutral(*humaneva))}) {
    const ConstraintSet set = ShippedSet(set_name, *skeleton);
    const PoseCheck r = CheckPose(set, pose);
    INFO(set_name);
    CHECK(r.Fired(set).empty());
    // The rest angles the definitions describe.
    auto angle = [&](const std::string& n) { return r.angles[set.Find(n)]; };
    CHECK(angle("Leg2ThighPlane_L") == Approx(96).margin(5));
    CHECK(angle("Shoulder2Shoulder") > 150);
    if (std::string(set_name) == "h36m") {
      CHECK(angle("HeadPlane2TorsoPlane") < 5);
      CHECK(angle("Thigh2TorsoPlane_R") == Approx(90).margin(5));
      CHECK(angle("Spine2Hip_L") == Approx(90).margin(10));
    } else {
      CHECK(angle("Thigh2TorsoPlane_R") < 10);
      CHECK(angle("Arm2ShoulderPlane_L") < 10);
    }
  }
}

TEST_CASE("impossible poses fire the expected constraint (h36m, Table 1 ranges)") {
  const auto s = ShippedSkeleton("h36m").skeleton;
  const ConstraintSet set = ShippedSet("h36m", *s);
  const Pose neutral = H36mNeutral(*s);
  const BodyAxes ax = Axes(*s, neutral, "LHip", "RHip", "Hips", "Thorax");

  SECTION("knee bent backwards") {
    Pose p = neutral;
    // Swing the left shin forward (hyperextension) by 50 degrees about the knee's lateral axis.
    Rotate(*s, &p, {"LFoot"}, At(*s, p, "LKnee"), ax.left, -50);
    const PoseCheck r = CheckPose(set, p);
    CHECK(r.Fires(set, "Leg2ThighPlane_L"));
    CHECK(r.Fired(set) == std::vector<std::string>{"Leg2ThighPlane_L"});
    // Bending it the normal way (90 degrees of flexion) is fine.
    Pose q = neutral;
    Rotate(*s, &q, {"LFoot"}, At(*s, q, "LKnee"), ax.left, 90);
    CHECK(CheckPose(set, q).Fired(set).empty());
  }
  SECTION("head rotated 180 degrees") {
    Pose p = neutral;
    Rotate(*s, &p, {"Neck", "Head"}, At(*s, p, "Thorax"), At(*s, p, "Head") - At(*s, p, "Thorax"),
           180);
    const PoseCheck r = CheckPose(set, p);
    CHECK(r.Fired(set) == std::vector<std::string>{"HeadPlane2TorsoPlane"});
    CHECK(r.angles[set.Find("HeadPlane2TorsoPlane")] > 170);
    // Looking over the shoulder (90 degrees) is fine.
    Pose q = neutral;
    Rotate(*s, &q, {"Neck", "Head"}, At(*s, q, "Thorax"), At(*s, q, "Head") - At(*s, q, "Thorax"),
           90);
    CHECK(CheckPose(set, q).Fired(set).empty());
  }
  SECTION("arm crossing through the torso") {
    Pose p = neutral;
    // The whole left arm swung through the chest to the right side.
    Rotate(*s, &p, {"LShoulder", "LElbow", "LWrist"}, At(*s, p, "Thorax"), ax.up, 160);
    const PoseCheck r = CheckPose(set, p);
    CHECK(r.Fires(set, "Shoulder2Shoulder"));
    CHECK(r.Fires(set, "Shoulder2Hip_L"));
    CHECK_FALSE(r.Fires(set, "Shoulder2Hip_R"));
  }
  SECTION("legs split beyond 180 degrees") {
    Pose p = neutral;
    // Front split of 200 degrees: left thigh 100 degrees forward, right thigh 100 degrees back.
    Rotate(*s, &p, {"LKnee", "LFoot"}, At(*s, p, "LHip"), ax.left, -100);
    Rotate(*s, &p, {"RKnee", "RFoot"}, At(*s, p, "RHip"), ax.left, 100);
    const PoseCheck r = CheckPose(set, p);
    CHECK(r.Fires(set, "Thigh2TorsoPlane_R"));
    CHECK(r.Fired(set) == std::vector<std::string>{"Thigh2TorsoPlane_R"});
    // A 120-degree stride is fine.
    Pose q = neutral;
    Rotate(*s, &q, {"LKnee", "LFoot"}, At(*s, q, "LHip"), ax.left, -80);
    Rotate(*s, &q, {"RKnee", "RFoot"}, At(*s, q, "RHip"), ax.left, 40);
    CHECK(CheckPose(set, q).Fired(set).empty());
  }
}

TEST_CASE("impossible poses fire the expected constraint (humaneva, Table 1 ranges)") {
  const auto s = ShippedSkeleton("humaneva").skeleton;
  const ConstraintSet set = ShippedSet("humaneva", *s);
  const Pose neutral = HumanEvaNeutral(*s);
  const BodyAxes ax = Axes(*s, neutral, "LHip", "RHip", "Pelvis", "Thorax");

  Pose knee = neutral;
  Rotate(*s, &knee, {"RAnkle"}, At(*s, knee, "RKnee"), ax.left, -50);
  CHECK(CheckPose(set, knee).Fired(set) == std::vector<std::string>{"Leg2ThighPlane_R"});

  // HumanEva has no face joint: the head turning is invisible, the head folded backwards is not.
  Pose head = neutral;
  Rotate(*s, &head, {"Head"}, At(*s, head, "Thorax"), ax.left, 180);
  CHECK(CheckPose(set, head).Fired(set) == std::vector<std::string>{"Neck2Spine"});

  Pose arm = neutral;
  Rotate(*s, &arm, {"RShoulder", "RElbow", "RWrist"}, At(*s, arm, "Thorax"), ax.up, -160);
  CHECK(CheckPose(set, arm).Fires(set, "Shoulder2Shoulder"));

  Pose front = neutral;
  Rotate(*s, &front, {"LKnee", "LAnkle"}, At(*s, front, "LHip"), ax.left, -100);
  Rotate(*s, &front, {"RKnee", "RAnkle"}, At(*s, front, "RHip"), ax.left, 100);
  const PoseCheck f = CheckPose(set, front);
  CHECK(f.Fires(set, "Thigh2TorsoPlane_L"));
  CHECK(f.Fires(set, "Thigh2TorsoPlane_R"));

  Pose side = neutral;
  Rotate(*s, &side, {"LKnee", "LAnkle"}, At(*s, side, "LHip"), ax.forward, 100);
  Rotate(*s, &side, {"RKnee", "RAnkle"}, At(*s, side, "RHip"), ax.forward, -100);
  const PoseCheck sd = CheckPose(set, side);
  CHECK(sd.Fires(set, "Thigh2TorsoPlane_L"));
  CHECK(sd.Fires(set, "Thigh2TorsoPlane_R"));

  // Raising an arm above the shoulder leaves the range HumanEva's motion stays in.
  Pose raise = neutral;
  Rotate(*s, &raise, {"LElbow", "LWrist"}, At(*s, raise, "LShoulder"), ax.forward, 150);
  CHECK(CheckPose(set, raise).Fired(set) == std::vector<std::string>{"Arm2ShoulderPlane_L"});
}

TEST_CASE("degenerate vectors are reported as such, never as NaN") {
  const auto s = ShippedSkeleton("h36m").skeleton;
  const ConstraintSet set = ShippedSet("h36m", *s);
  const Pose neutral = H36mNeutral(*s);

  SECTION("zero-length bone") {
    Pose p = neutral;
    const Eigen::Vector3f hip = At(*s, p, "LHip");
    Eigen::Map<Eigen::Vector3f>(p.data() + 3 * s->Index("LKnee")) = hip;
    const PoseCheck r = CheckPose(set, p);
    for (const char* n : {"Leg2ThighPlane_L", "Thigh2TorsoPlane_L"}) {
      INFO(n);
      CHECK(r.status[set.Find(n)] == AngleStatus::kDegenerate);
      CHECK(r.angles[set.Find(n)] == kUndefinedAngle);
    }
    CHECK(r.Fired(set) == std::vector<std::string>{"Leg2ThighPlane_L", "Thigh2TorsoPlane_L"});
  }
  SECTION("collinear plane vectors") {
    Pose p = neutral;
    // Left thigh straight out sideways, in line with the pelvis->hip bone: no thigh plane.
    const Eigen::Vector3f hip = At(*s, p, "LHip");
    const Eigen::Vector3f out = hip - At(*s, p, "Hips");
    Eigen::Map<Eigen::Vector3f>(p.data() + 3 * s->Index("LKnee")) = hip + 3.0f * out;
    Eigen::Map<Eigen::Vector3f>(p.data() + 3 * s->Index("LFoot")) = hip + 6.0f * out;
    const PoseCheck r = CheckPose(set, p);
    CHECK(r.status[set.Find("Leg2ThighPlane_L")] == AngleStatus::kDegenerate);
    CHECK(r.status[set.Find("Thigh2TorsoPlane_L")] != AngleStatus::kDegenerate);
  }
  SECTION("all joints on one point, and NaN input") {
    Pose p(neutral.size(), 0.5f);
    PoseCheck r = CheckPose(set, p);
    for (int c = 0; c < set.num_constraints(); ++c) CHECK(r.status[c] == AngleStatus::kDegenerate);
    Pose q = neutral;
    q[3 * s->Index("Head") + 1] = std::nanf("");
    r = CheckPose(set, q);
    CHECK(r.status[set.Find("HeadPlane2TorsoPlane")] == AngleStatus::kDegenerate);
    for (float a : r.angles) CHECK_FALSE(std::isnan(a));
  }
  SECTION("degenerate frames do not count as valid") {
    std::vector<float> frames = neutral;
    Pose p(neutral.size(), 0.5f);
    frames.insert(frames.end(), p.begin(), p.end());
    const Motion m(s, 50, frames);
    const CheckSummary sum = Summarize(set, Check(set, m));
    CHECK(sum.frames == 2);
    CHECK(sum.valid_frames == 1);
    CHECK(sum.degenerate_frames == 1);
    CHECK(sum.violating_frames == 0);
    CHECK(sum.constraints[0].degenerate == 1);
  }
}

TEST_CASE("summary: violation rates, worst frames, valid-frame share") {
  const auto s = ShippedSkeleton("h36m").skeleton;
  const ConstraintSet set = ShippedSet("h36m", *s);
  const Pose neutral = H36mNeutral(*s);
  const BodyAxes ax = Axes(*s, neutral, "LHip", "RHip", "Hips", "Thorax");
  std::vector<float> frames;
  for (int t = 0; t < 10; ++t) {
    Pose p = neutral;
    if (t >= 6) Rotate(*s, &p, {"LFoot"}, At(*s, p, "LKnee"), ax.left, -10.0f - 15.0f * (t - 5));
    frames.insert(frames.end(), p.begin(), p.end());
  }
  const Motion m(s, 50, frames);
  const CheckResult r = Check(set, m);
  const CheckSummary sum = Summarize(set, r, 3);
  const int knee = set.Find("Leg2ThighPlane_L");
  // The neutral knee is at ~100 degrees; 25..70 degrees of hyperextension: frames 6..9 violate.
  CHECK(sum.violating_frames == 4);
  CHECK(sum.valid_frames == 6);
  CHECK(sum.valid_frame_share() == Approx(0.6));
  CHECK(sum.constraints[knee].below == 4);
  CHECK(sum.constraints[knee].violation_rate == Approx(0.4));
  CHECK(sum.constraints[knee].worst_frame == 9);
  CHECK(sum.constraints[knee].worst_excess_deg == Approx(80 - r.angle(9, knee)));
  REQUIRE(sum.worst_frames.size() == 3);
  CHECK(sum.worst_frames[0].frame == 9);
  CHECK(sum.worst_frames[1].frame == 8);
  CHECK(sum.worst_frames[0].constraints == std::vector<int>{knee});
  for (int c = 0; c < set.num_constraints(); ++c) {
    if (c != knee) CHECK(sum.constraints[c].violations() == 0);
  }
  const auto humaneva = ShippedSkeleton("humaneva").skeleton;
  CHECK_THROWS_WITH(Check(set, Motion(humaneva, 60, std::vector<float>(15 * 3, 0.0f))),
                    Catch::Contains("17 joints") && Catch::Contains("15 joints"));
}

TEST_CASE("the compiled program shares vectors and rejects bad options") {
  const auto s = ShippedSkeleton("h36m").skeleton;
  const ConstraintSet set = ShippedSet("h36m", *s);
  // The torso's forward normal is one register for HeadPlane2TorsoPlane and both Thigh2TorsoPlane.
  const int l = set.Find("Thigh2TorsoPlane_L"), r = set.Find("Thigh2TorsoPlane_R");
  CHECK(set.constraint(l).b == set.constraint(r).b);
  CHECK(set.constraint(l).b_text == "normal(bone(Thorax, RHip), bone(Thorax, LHip))");
  // The right thigh plane is the mirrored expression with the cross product reversed.
  CHECK(set.constraint(set.Find("Leg2ThighPlane_R")).b_text ==
        "normal(bone(Hips, RHip), bone(RHip, RKnee))");
  for (int k = 0; k < set.num_registers(); ++k) {
    for (int m = 0; m < k; ++m) {
      const VectorOp& a = set.ops()[k];
      const VectorOp& b = set.ops()[m];
      CHECK_FALSE((a.kind == b.kind && a.x == b.x && a.y == b.y));
    }
    if (set.ops()[k].kind == VectorOp::Kind::kCross) {
      CHECK(set.ops()[k].x < k);
      CHECK(set.ops()[k].y < k);
    }
  }
  DegeneracyOptions bad;
  bad.min_normal_sine = 1.5f;
  CHECK_THROWS_WITH(AngleChecker(set, bad),
                    Catch::Contains("min_normal_sine") && Catch::Contains("1.5"));
  bad = DegeneracyOptions{};
  bad.min_bone_length = -1;
  CHECK_THROWS_WITH(AngleChecker(set, bad), Catch::Contains("min_bone_length"));
}
