#include "config/skeleton_config.h"

#include <catch2/catch.hpp>
#include <fstream>

#include "config/config_paths.h"
#include "core/error.h"
#include "test_support.h"

using namespace motionfork;

namespace {
SkeletonConfig Shipped(const std::string& name) {
  return LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", name));
}
// Joint indices of a part after the root is removed (the papers' numbering).
std::vector<int> RootRemoved(const BodyPart& part) {
  std::vector<int> out;
  for (int j : part.joints) out.push_back(j - 1);
  return out;
}
std::vector<int> Range(int a, int b) {
  std::vector<int> v;
  for (int i = a; i <= b; ++i) v.push_back(i);
  return v;
}
}  // namespace

TEST_CASE("h36m: 32 -> 17 joints with the published parents and parts") {
  const SkeletonConfig c = Shipped("h36m");
  REQUIRE(c.source->num_joints() == 32);
  CHECK(c.source->parents() == std::vector<int>{-1, 0,  1,  2,  3,  4,  0,  6,  7,  8,  9,
                                                0,  11, 12, 13, 14, 12, 16, 17, 18, 19, 20,
                                                19, 22, 12, 24, 25, 26, 27, 28, 27, 30});
  REQUIRE(c.selection);
  CHECK(c.selection->source_index ==
        std::vector<int>{0, 1, 2, 3, 6, 7, 8, 12, 13, 14, 15, 17, 18, 19, 25, 26, 27});
  CHECK(c.skeleton->parents() ==
        std::vector<int>{-1, 0, 1, 2, 0, 4, 5, 0, 7, 8, 9, 8, 11, 12, 8, 14, 15});
  const Partition& two = c.skeleton->GetPartition();
  CHECK(RootRemoved(two.parts[0]) == Range(0, 5));
  CHECK(RootRemoved(two.parts[1]) == Range(6, 15));
  const Partition& five = c.skeleton->GetPartition("five");
  REQUIRE(five.parts.size() == 5);
  CHECK(RootRemoved(five.parts[0]) == Range(0, 2));
  CHECK(RootRemoved(five.parts[1]) == Range(3, 5));
  CHECK(RootRemoved(five.parts[2]) == Range(6, 9));
  CHECK(RootRemoved(five.parts[3]) == Range(10, 12));
  CHECK(RootRemoved(five.parts[4]) == Range(13, 15));
  // VideoPose3D's joints_left / joints_right for the 17-joint skeleton.
  for (auto [l, r] :
       std::vector<std::pair<int, int>>{{4, 1}, {5, 2}, {6, 3}, {11, 14}, {12, 15}, {13, 16}}) {
    CHECK(c.skeleton->Mirror(l) == r);
  }
}

TEST_CASE("humaneva: 15 joints with the published parents and parts") {
  const SkeletonConfig c = Shipped("humaneva");
  CHECK_FALSE(c.selection);
  CHECK(c.skeleton->parents() == std::vector<int>{-1, 0, 1, 2, 3, 1, 5, 6, 0, 8, 9, 0, 11, 12, 1});
  const Partition& p = c.skeleton->GetPartition();
  CHECK(RootRemoved(p.parts[0]) == Range(7, 12));
  std::vector<int> upper = Range(0, 6);
  upper.push_back(13);
  CHECK(RootRemoved(p.parts[1]) == upper);
  for (auto [l, r] :
       std::vector<std::pair<int, int>>{{2, 5}, {3, 6}, {4, 7}, {8, 11}, {9, 12}, {10, 13}}) {
    CHECK(c.skeleton->Mirror(l) == r);
  }
}

TEST_CASE("bandai: 22 -> 17 joints mirroring the H36M layout") {
  const SkeletonConfig c = Shipped("bandai");
  CHECK(c.source->num_joints() == 22);
  CHECK(c.skeleton->num_joints() == 17);
  // Same tree shape as H36M's except the shoulders hang on Chest (index 8) naturally.
  CHECK(c.skeleton->parents() ==
        std::vector<int>{-1, 0, 1, 2, 0, 4, 5, 0, 7, 8, 9, 8, 11, 12, 8, 14, 15});
  CHECK(RootRemoved(c.skeleton->GetPartition().parts[0]) == Range(0, 5));
}

TEST_CASE("skeleton configs report YAML and structure problems with file and line") {
  testing::TempDir dir;
  const std::string path = dir.file("bad.yaml");
  { std::ofstream(path) << "name: bad\njoints:\n  - [a, ~]\n  - [b, c]\n"; }
  CHECK_THROWS_WITH(LoadSkeletonConfig(path),
                    Catch::Contains("bad.yaml") && Catch::Contains("unknown parent 'c'"));
  { std::ofstream(path) << "name: bad\njoints:\n  - [a, ~]\n  - b\n"; }
  CHECK_THROWS_WITH(LoadSkeletonConfig(path), Catch::Contains("bad.yaml:line 4"));
  { std::ofstream(path) << "name: [unclosed\n"; }
  CHECK_THROWS_AS(LoadSkeletonConfig(path), FormatError);
  CHECK_THROWS_WITH(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "nope"),
                    Catch::Contains("bandai") && Catch::Contains("h36m"));
}

#include "core/joint_selection.h"
#include "io/npy.h"

TEST_CASE("motions from files are conformed to a config's skeleton by names or by joint count") {
  const SkeletonConfig bandai = Shipped("bandai");
  const Motion m = testing::MakeWalkingMotion(4);  // the 17 protocol joints, Bandai names
  // Protocol names in another order -> re-ordered onto the protocol skeleton.
  JointSelectionSpec rev;
  rev.name = "reordered";
  rev.keep = {"Hips", "Spine", "Chest", "Head", "Neck", "UpperLeg_R"};
  rev.reparent = {{"Neck", "Chest"}, {"Head", "Chest"}};
  // (partial skeletons lack joints: must fail naming them)
  const Motion partial = ApplySelection(m, SelectJoints(m.skeleton(), rev));
  CHECK_THROWS_WITH(ConformToSkeleton(partial, bandai),
                    Catch::Contains("lacks joints") && Catch::Contains("Hand_R"));
  const Motion same = ConformToSkeleton(m, bandai);
  CHECK(same.skeleton().SameStructure(*bandai.skeleton));
  CHECK(same.positions() == m.positions());
  // Anonymous [T, 17, 3] -> bound by index.
  const Motion anon(std::make_shared<const Skeleton>(Skeleton::Anonymous(17)), 30, m.positions());
  CHECK(ConformToSkeleton(anon, bandai).positions() == m.positions());
  const Motion anon5(std::make_shared<const Skeleton>(Skeleton::Anonymous(5)), 30,
                     std::vector<float>(4 * 5 * 3, 0.f));
  CHECK_THROWS_WITH(ConformToSkeleton(anon5, bandai), Catch::Contains("5 unnamed joints"));
}
