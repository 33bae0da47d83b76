#include "core/skeleton.h"

#include <catch2/catch.hpp>

#include "test_support.h"

using namespace motionfork;

TEST_CASE("skeleton builds from names, looks joints up and mirrors pairs") {
  auto s = testing::MakeHumanoid();
  REQUIRE(s->num_joints() == 17);
  CHECK(s->Index("Hips") == 0);
  CHECK(s->parent(s->Index("UpperArm_L")) == s->Index("Chest"));
  CHECK(s->Mirror(s->Index("Hand_L")) == s->Index("Hand_R"));
  CHECK(s->Mirror(s->Index("Head")) == s->Index("Head"));
  CHECK_FALSE(s->Find("Tail"));
  CHECK_THROWS_WITH(s->Index("Tail"),
                    Catch::Contains("no joint 'Tail'") && Catch::Contains("Hips"));
}

TEST_CASE("skeleton partitions resolve subtrees and rest, and must cover every joint") {
  auto s = testing::MakeHumanoid();
  const Partition& p = s->GetPartition();
  REQUIRE(p.parts.size() == 2);
  CHECK(p.parts[0].joints == std::vector<int>{1, 2, 3, 4, 5, 6});
  CHECK(p.parts[1].joints == std::vector<int>{7, 8, 9, 10, 11, 12, 13, 14, 15, 16});

  SkeletonSpec spec;
  spec.name = "tiny";
  spec.joint_names = {"root", "a", "b"};
  spec.parent_names = {"", "root", "a"};
  spec.partitions = {PartitionSpec{"bad", {PartSpec{"p", {"a"}, {}, false}}}};
  CHECK_THROWS_WITH(Skeleton::Build(spec), Catch::Contains("missing: b"));
  spec.partitions = {PartitionSpec{
      "bad", {PartSpec{"p", {"a", "b"}, {}, false}, PartSpec{"q", {"b"}, {}, false}}}};
  CHECK_THROWS_WITH(Skeleton::Build(spec), Catch::Contains("'b' is in parts 'p' and 'q'"));
}

TEST_CASE("skeleton validation names the offending joint") {
  CHECK_THROWS_WITH(Skeleton::FromParents("x", {"a", "b"}, {-1, 1}),
                    Catch::Contains("'b'") && Catch::Contains("parent listed before it"));
  CHECK_THROWS_WITH(Skeleton::FromParents("x", {"a", "a"}, {-1, 0}),
                    Catch::Contains("appears twice"));
  CHECK_THROWS_WITH(Skeleton::FromParents("x", {"a", "b"}, {0, 0}),
                    Catch::Contains("must be the root"));
  CHECK_THROWS_WITH(Skeleton::FromParents("x", {"a", "b"}, {-1, -1}),
                    Catch::Contains("only the first joint may be a root"));
  CHECK_THROWS_WITH(Skeleton::FromParents("x", {}, {}), Catch::Contains("at least one joint"));
  SkeletonSpec spec;
  spec.name = "x";
  spec.joint_names = {"a", "b"};
  spec.parent_names = {"", "nope"};
  CHECK_THROWS_WITH(Skeleton::Build(spec), Catch::Contains("unknown parent 'nope'"));
  CHECK_THROWS_WITH(Skeleton::FromParents("x", {"a", "b", "c"}, {-1, 0, 0}, {{1, 1}}),
                    Catch::Contains("bad left/right pair"));
}

TEST_CASE("subtree lists a joint and everything below it") {
  auto s = testing::MakeHumanoid();
  const auto sub = s->Subtree(s->Index("Chest"));
  CHECK(sub.size() == 9);  // Chest Neck Head + 2 x 3 arm joints
  CHECK(sub.front() == s->Index("Chest"));
}
