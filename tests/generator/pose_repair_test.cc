// PoseRepair on the Bandai skeleton with the shipped Bandai constraint set (angle ranges and the
// rigid pelvis): poses built from the demo walk, damaged in known ways.
#include "generator/inference/pose_repair.h"

#include <cmath>

#include "bodyparts/part_plan.h"
#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "core/demo_motion.h"
#include "torch_catch.h"

using namespace motionfork;

namespace {

struct Setup {
  std::shared_ptr<const Skeleton> skeleton =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "bandai")).skeleton;
  ConstraintSetSpec spec =
      LoadConstraintConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "constraints", "bandai"));
  PartPlan parts = MakePartPlan(*skeleton);
  int J = skeleton->num_joints();

  // The demo walk, root-relative (root at the origin): [frames, J, 3].
  torch::Tensor Walk(int frames) const {
    DemoWalkOptions o;
    o.frames = frames;
    const Motion m = MakeDemoWalk(skeleton, o);
    torch::Tensor x =
        torch::from_blob(const_cast<float*>(m.positions().data()), {frames, J, 3}).clone();
    return x - x.select(1, 0).unsqueeze(1);
  }
  int Joint(const char* name) const { return skeleton->Index(name); }
  // Frames breaking some range, by the checker.
  int Broken(const torch::Tensor& poses) const {
    const ConstraintSet set = ConstraintSet::Build(spec, *skeleton);
    const AngleChecker checker(set);
    const torch::Tensor c = poses.contiguous();
    const int n = static_cast<int>(c.size(0)), C = set.num_constraints();
    std::vector<AngleStatus> status(static_cast<size_t>(n) * C);
    checker.Run(c.data_ptr<float>(), n, nullptr, status.data());
    int broken = 0;
    for (int t = 0; t < n; ++t) {
      bool any = false;
      for (int k = 0; k < C; ++k) any = any || IsViolation(status[static_cast<size_t>(t) * C + k]);
      broken += any;
    }
    return broken;
  }
};

float Distance(const torch::Tensor& pose, int a, int b) {
  return (pose[a] - pose[b]).norm().item<float>();
}

}  // namespace

TEST_CASE("rigid pelvis: put back on the template layout with legs and upper body carried along") {
  Setup s;
  const torch::Tensor templ = s.Walk(20);
  REQUIRE(s.Broken(templ) == 0);
  // Damage: spine base pushed 3 cm sideways with the whole upper body, left hip 2 cm up with its
  // leg.
  torch::Tensor poses = templ.clone();
  const int spine = s.Joint("Spine"), hip_l = s.Joint("UpperLeg_L"), hip_r = s.Joint("UpperLeg_R");
  for (int j : s.skeleton->Subtree(spine)) poses.select(1, j).select(1, 0).add_(0.03f);
  for (int j : s.skeleton->Subtree(hip_l)) poses.select(1, j).select(1, 1).add_(0.02f);
  REQUIRE(s.Broken(poses) == 20);
  const torch::Tensor before = poses.clone();
  const PoseRepair repair(s.spec, *s.skeleton, s.parts);
  const PoseRepairStats stats = repair.Repair(poses, templ, {false, false});
  CHECK(stats.poses == 20);
  CHECK(stats.still_broken == 0);
  CHECK(s.Broken(poses) == 0);
  for (int t = 0; t < 20; ++t) {
    const torch::Tensor p = poses[t], q = templ[t], b = before[t];
    // The pelvis triangle has the template's shape again.
    CHECK(Distance(p, spine, hip_l) == Approx(Distance(q, spine, hip_l)).margin(1e-5));
    CHECK(Distance(p, hip_l, hip_r) == Approx(Distance(q, hip_l, hip_r)).margin(1e-5));
    CHECK(Distance(p, 0, spine) == Approx(Distance(q, 0, spine)).margin(1e-5));
    // Bones inside the carried subtrees keep their lengths (thigh, shin; spine to chest).
    CHECK(Distance(p, hip_l, s.Joint("LowerLeg_L")) ==
          Approx(Distance(b, hip_l, s.Joint("LowerLeg_L"))).margin(1e-5));
    CHECK(Distance(p, spine, s.Joint("Chest")) ==
          Approx(Distance(b, spine, s.Joint("Chest"))).margin(1e-5));
  }
}

TEST_CASE("angle repair: a backward knee is bent forward again and valid poses are not touched") {
  Setup s;
  const torch::Tensor templ = s.Walk(30);
  torch::Tensor poses = templ.clone();
  const int hip = s.Joint("UpperLeg_L"), knee = s.Joint("LowerLeg_L"), ankle = s.Joint("Foot_L");
  for (int t = 10; t < 20; ++t) {  // knee 8 cm behind the hip-ankle line
    poses[t][knee] = 0.5f * (poses[t][hip] + poses[t][ankle]) - torch::tensor({0.0f, 0.0f, 0.08f});
  }
  REQUIRE(s.Broken(poses) == 10);
  const torch::Tensor before = poses.clone();
  const PoseRepair repair(s.spec, *s.skeleton, s.parts);
  const PoseRepairStats stats = repair.Repair(poses, templ, {false, false});
  CHECK(stats.still_broken == 0);
  CHECK(s.Broken(poses) == 0);
  // Untouched where nothing was broken (the rigid step leaves a valid pelvis where it was, to
  // float rounding).
  CHECK((poses.slice(0, 0, 10) - before.slice(0, 0, 10)).abs().max().item<float>() < 1e-5);
  CHECK((poses.slice(0, 20) - before.slice(0, 20)).abs().max().item<float>() < 1e-5);
  // Repaired frames moved little, and only the left leg.
  const torch::Tensor moved = (poses - before).norm(2, -1).slice(0, 10, 20);  // [10, J]
  CHECK(moved.max().item<float>() < 0.12f);
  for (int j = 0; j < s.J; ++j) {
    if (j == knee || j == ankle || j == hip || j == s.Joint("LowerLeg_R") ||
        j == s.Joint("Foot_R") || j == s.Joint("UpperLeg_R"))
      continue;
    CHECK(moved.select(1, j).max().item<float>() < 1e-5);
  }
}

TEST_CASE("angle repair: a pose comes out the same alone as in any batch") {
  Setup s;
  const torch::Tensor templ = s.Walk(30);
  torch::Tensor poses = templ.clone();
  const int hip = s.Joint("UpperLeg_L"), knee = s.Joint("LowerLeg_L"), ankle = s.Joint("Foot_L");
  // Knees behind the hip-ankle line by 4 to 13 cm: barely broken to far out, so that the poses
  // need different numbers of steps.
  for (int t = 10; t < 20; ++t) {
    poses[t][knee] = 0.5f * (poses[t][hip] + poses[t][ankle]) -
                     torch::tensor({0.0f, 0.0f, 0.04f + 0.01f * (t - 10)});
  }
  REQUIRE(s.Broken(poses) >= 8);
  const PoseRepair repair(s.spec, *s.skeleton, s.parts);
  torch::Tensor batch = poses.clone();
  repair.Repair(batch, templ, {false, false});
  CHECK(s.Broken(batch) == 0);
  for (int t = 10; t < 20; ++t) {
    torch::Tensor alone = poses.slice(0, t, t + 1).clone();
    repair.Repair(alone, templ.slice(0, t, t + 1).clone(), {false, false});
    INFO("frame " << t);
    CHECK((alone[0] - batch[t]).abs().max().item<float>() < 1e-6f);
  }
}

TEST_CASE("repair keeps part control: a fixed part stays identical across samples") {
  Setup s;
  const torch::Tensor walk = s.Walk(8);
  // Four "samples" of 8 frames: same legs, upper bodies turned by different angles about the
  // vertical (and the pelvis a little off), as a generator with fixed legs would give.
  std::vector<torch::Tensor> samples;
  for (int k = 0; k < 4; ++k) {
    torch::Tensor x = walk.clone();
    const float a = 0.15f * k, c = std::cos(a), sn = std::sin(a);
    for (int j : s.skeleton->Subtree(s.Joint("Spine"))) {
      const torch::Tensor px = x.select(1, j).select(1, 0).clone(),
                          pz = x.select(1, j).select(1, 2).clone();
      x.select(1, j).select(1, 0).copy_(c * px + sn * pz);
      x.select(1, j).select(1, 2).copy_(-sn * px + c * pz);
    }
    for (int j : s.skeleton->Subtree(s.Joint("UpperLeg_L")))
      x.select(1, j).select(1, 1).add_(0.015f);
    samples.push_back(x);
  }
  for (int fixed_part = 0; fixed_part < 2; ++fixed_part) {
    torch::Tensor poses = torch::cat(samples, 0);  // [32, J, 3]
    if (fixed_part == 1) {                         // upper body shared, legs varied
      poses = torch::cat(samples, 0);
      for (int k = 0; k < 4; ++k) {
        for (int j : s.parts.nodes[1])
          poses.slice(0, 8 * k, 8 * k + 8).select(1, j + 1).copy_(samples[0].select(1, j + 1));
        for (int j : s.parts.nodes[0])
          poses.slice(0, 8 * k, 8 * k + 8).select(1, j + 1).add_(0.01f * k);
      }
    }
    const torch::Tensor templ = torch::cat({walk, walk, walk, walk}, 0);
    const PoseRepair repair(s.spec, *s.skeleton, s.parts);
    std::vector<bool> fixed = {fixed_part == 0, fixed_part == 1};
    repair.Repair(poses, templ, fixed);
    INFO("fixed part " << s.parts.names[fixed_part]);
    for (int64_t n : s.parts.nodes[fixed_part]) {
      for (int k = 1; k < 4; ++k) {
        CHECK(torch::equal(poses.slice(0, 8 * k, 8 * k + 8).select(1, n + 1),
                           poses.slice(0, 0, 8).select(1, n + 1)));
      }
    }
  }
}

TEST_CASE("repair names a rigid joint the skeleton does not have") {
  Setup s;
  s.spec.rigid = {{"UpperLeg_L", "Tail"}};
  CHECK_THROWS_WITH(PoseRepair(s.spec, *s.skeleton, s.parts), Catch::Contains("Tail"));
  s.spec.rigid = {{"Hips", "Spine"}};
  CHECK_THROWS_WITH(PoseRepair(s.spec, *s.skeleton, s.parts), Catch::Contains("root"));
}
