// Constraint YAML: the shipped files, writing back, and clear errors for malformed files.
#include "config/constraint_config.h"

#include <catch2/catch.hpp>
#include <fstream>

#include "core/error.h"
#include "fixtures.h"
#include "test_support.h"

using namespace motionfork;
using namespace motionfork::testing;

namespace {

const char* const kGood = R"(
name: demo
skeleton: h36m
sides: [L, R]
vectors:
  torso_forward: normal(bone(Thorax, {other}Hip), bone(Thorax, {side}Hip))
constraints:
  - name: Knee
    per_side: true
    a: bone({side}Knee, {side}Foot)
    b: normal(bone({side}Hip, {side}Knee), bone(Hips, {side}Hip))
    range: [80, 180]
    note: "knee: flexion"
  - name: Thigh
    per_side: true
    a: bone({side}Hip, {side}Knee)
    b: torso_forward
    range: [0, 140.5]
)";

// Parses text in which `from` is replaced by `to`; returns the FormatError message ("" if none).
std::string ErrorOf(const std::string& text, bool bind = false) {
  try {
    const ConstraintSetSpec spec = ParseConstraintConfig(text, "bad.yaml");
    if (bind) ConstraintSet::Build(spec, *ShippedSkeleton("h36m").skeleton);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "";
}
std::string Replace(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("constraint YAML: parsed into per-side definitions with expressions and ranges") {
  const ConstraintSetSpec spec = ParseConstraintConfig(kGood, "good.yaml");
  CHECK(spec.name == "demo");
  CHECK(spec.skeleton == "h36m");
  REQUIRE(spec.constraints.size() == 2);
  const ConstraintSpec& k = spec.constraints[0];
  CHECK(k.per_side);
  CHECK(k.a.kind == VectorExpr::Kind::kBone);
  CHECK(k.a.from == "{side}Knee");
  CHECK(k.b.kind == VectorExpr::Kind::kNormal);
  CHECK(ToString(k.b) == "normal(bone({side}Hip, {side}Knee), bone(Hips, {side}Hip))");
  CHECK(k.lower_deg == 80);
  CHECK(k.upper_deg == 180);
  CHECK(k.note == "knee: flexion");
  // Named vectors are expanded where they are used.
  CHECK(ToString(spec.constraints[1].b) ==
        "normal(bone(Thorax, {other}Hip), bone(Thorax, {side}Hip))");
  CHECK(spec.constraints[1].upper_deg == 140.5);

  const ConstraintSet set = ConstraintSet::Build(spec, *ShippedSkeleton("h36m").skeleton);
  REQUIRE(set.num_constraints() == 4);
  CHECK(set.constraint(0).name == "Knee_L");
  CHECK(set.constraint(1).name == "Knee_R");
  CHECK(set.constraint(1).side == Side::kRight);
  CHECK(set.constraint(0).mirror == 1);
  CHECK(set.constraint(1).a_text == "bone(RKnee, RFoot)");
  // Right side: names substituted and the cross product reversed.
  CHECK(set.constraint(1).b_text == "normal(bone(Hips, RHip), bone(RHip, RKnee))");
  CHECK(set.constraint(3).b_text == "normal(bone(Thorax, RHip), bone(Thorax, LHip))");
  CHECK(set.constraint(2).b == set.constraint(3).b);
}

TEST_CASE(
    "constraint YAML: every shipped set loads, binds to its skeleton and writes back unchanged") {
  for (const std::string name : {"h36m", "humaneva", "bandai"}) {
    INFO(name);
    const ConstraintSetSpec spec = ShippedConstraints(name);
    CHECK(spec.name == name);
    CHECK(spec.skeleton == name);
    const ConstraintSet set = ConstraintSet::Build(spec, *ShippedSkeleton(name).skeleton);
    CHECK(set.num_constraints() >= 8);
    for (const ConstraintSpec& c : spec.constraints) CHECK(c.has_range);
    const std::string text = FormatConstraintConfig(spec, "written back\nby a test");
    CHECK(text.rfind("# written back\n# by a test\n", 0) == 0);
    const ConstraintSetSpec again = ParseConstraintConfig(text, "again.yaml");
    REQUIRE(again.constraints.size() == spec.constraints.size());
    CHECK(again.vectors == spec.vectors);
    for (size_t i = 0; i < spec.constraints.size(); ++i) {
      const ConstraintSpec& a = spec.constraints[i];
      const ConstraintSpec& b = again.constraints[i];
      CHECK(a.name == b.name);
      CHECK(a.per_side == b.per_side);
      CHECK(a.a_text == b.a_text);
      CHECK(a.b_text == b.b_text);
      CHECK(ToString(a.b) == ToString(b.b));
      CHECK(a.lower_deg == b.lower_deg);
      CHECK(a.upper_deg == b.upper_deg);
      CHECK(a.note == b.note);
    }
  }
}

TEST_CASE("constraint YAML: the seed's Table 1 ranges are the shipped h36m and humaneva ranges") {
  const std::vector<std::tuple<std::string, std::string, double, double>> table = {
      {"h36m", "Neck2Spine", 0, 124},
      {"h36m", "HeadPlane2TorsoPlane", 0, 120},
      {"h36m", "Leg2ThighPlane", 80, 180},
      {"h36m", "Thigh2TorsoPlane", 0, 140},
      {"h36m", "UpperSpine2LowerSpine", 110, 180},
      {"h36m", "Shoulder2Hip", 0, 84},
      {"h36m", "Shoulder2Neck", 32, 134},
      {"h36m", "Shoulder2Shoulder", 83, 180},
      {"h36m", "Spine2Hip", 60, 120},
      {"humaneva", "Neck2Spine", 0, 50},
      {"humaneva", "Leg2ThighPlane", 72, 166},
      {"humaneva", "Thigh2TorsoPlane", 0, 58},
      {"humaneva", "Shoulder2Shoulder", 128, 180},
      {"humaneva", "Arm2ShoulderPlane", 0, 91}};
  std::map<std::string, int> count;
  for (const auto& [set, name, lo, hi] : table) {
    const ConstraintSetSpec spec = ShippedConstraints(set);
    bool found = false;
    for (const ConstraintSpec& c : spec.constraints) {
      if (c.name != name) continue;
      found = true;
      CHECK(c.lower_deg == lo);
      CHECK(c.upper_deg == hi);
    }
    INFO(set << " " << name);
    CHECK(found);
    count[set]++;
  }
  CHECK(ShippedConstraints("h36m").constraints.size() == size_t(count["h36m"]));
  CHECK(ShippedConstraints("humaneva").constraints.size() == size_t(count["humaneva"]));
}

TEST_CASE("constraint YAML: malformed files name the file, the constraint and the problem") {
  const std::string good = kGood;
  REQUIRE(ErrorOf(good, true).empty());
  struct Bad {
    std::string from, to, expect;
    bool bind;
  };
  const std::vector<Bad> cases = {
      {"bone({side}Knee, {side}Foot)", "bone({side}Knee, {side}Toe)", "unknown joint 'LToe'", true},
      {"bone(Hips, {side}Hip)", "bone(Pelvis, {side}Hip)", "unknown joint 'Pelvis'", true},
      {"    range: [80, 180]\n", "", "missing 'range: [lower, upper]'", false},
      {"range: [80, 180]", "range: [120, 80]", "lower bound 120 > upper bound 80", false},
      {"range: [80, 180]", "range: [80, 200]", "outside [0, 180]", false},
      {"range: [80, 180]", "range: [80, wide]", "'wide' is not a number", false},
      {"range: [80, 180]", "range: [80, 180]\n    anatomical: [90, 70]",
       "anatomical: lower bound 90 > upper bound 70", false},
      {"range: [80, 180]", "range: [80, 180]\n    anatomical: 80",
       "'anatomical' must be [lower, upper]", false},
      {"range: [80, 180]", "range: 80", "'range' must be [lower, upper]", false},
      {"a: bone({side}Knee, {side}Foot)", "a: elbow({side}Knee, {side}Foot)",
       "unknown vector kind 'elbow'", false},
      {"a: bone({side}Knee, {side}Foot)", "a: bone({side}Knee)", "expected ','", false},
      {"a: bone({side}Knee, {side}Foot)", "a: bone({left}Knee, {side}Foot)",
       "unknown placeholder '{left}'", false},
      {"a: bone({side}Knee, {side}Foot)", "a: torso_backward", "unknown vector 'torso_backward'",
       false},
      {"b: torso_forward", "b: normal(bone({side}Hip, {side}Knee), bone({side}Hip, {side}Knee))",
       "crosses a vector with itself", true},
      {"a: bone({side}Knee, {side}Foot)", "a: bone({side}Knee, {side}Knee)", "to itself", true},
      {"    per_side: true\n    a: bone({side}Hip", "    a: bone({side}Hip", "not per-side", false},
      {"    range: [0, 140.5]", "    rnage: [0, 140.5]", "unknown key 'rnage'", false},
      {"- name: Thigh", "- name: Knee", "used twice", false},
      // A paired joint written without a placeholder: the right instance would not mirror the left.
      {"b: torso_forward", "b: normal(bone(Thorax, RHip), bone(Thorax, LHip))",
       "not the mirror image", true},
  };
  for (const Bad& b : cases) {
    const std::string text = Replace(good, b.from, b.to);
    const std::string err = ErrorOf(text, b.bind);
    INFO("case: " << b.expect << "\nmessage: " << err);
    CHECK(err.find("bad.yaml") != std::string::npos);
    CHECK(err.find(b.expect) != std::string::npos);
    if (b.expect.find("rnage") == std::string::npos) {
      CHECK((err.find("constraint 'Thigh'") != std::string::npos ||
             err.find("constraint 'Knee'") != std::string::npos));
    }
    CHECK(err.find("line ") != std::string::npos);
  }
  // Cycles among named vectors, and files that are not constraint files at all.
  CHECK(ErrorOf("name: x\nvectors:\n  a: normal(b, bone(A, B))\n  b: a\nconstraints:\n  - {name: "
                "c, a: a, b: b, range: [0, 1]}\n")
            .find("refers to itself") != std::string::npos);
  CHECK(ErrorOf("name: x\nconstraints: []\n").find("non-empty list 'constraints'") !=
        std::string::npos);
  CHECK(ErrorOf("- just\n- a list\n").find("mapping") != std::string::npos);
  CHECK(ErrorOf("name: x\nconstraints:\n  - {a: bone(A, B), b: bone(B, C), range: [0, 1]}\n")
            .find("has no 'name'") != std::string::npos);
}

TEST_CASE("constraint YAML: files on disk, fitting mode without ranges") {
  TempDir dir;
  const std::string path = dir.file("mine.yaml");
  {
    std::ofstream f(path);
    f << Replace(kGood, "    range: [80, 180]\n", "");
  }
  try {
    LoadConstraintConfig(path);
    FAIL("expected a FormatError");
  } catch (const FormatError& e) {
    CHECK(std::string(e.what()).find(path) != std::string::npos);
    CHECK(std::string(e.what()).find("constraint 'Knee'") != std::string::npos);
  }
  ConstraintLoadOptions fitting;
  fitting.require_ranges = false;
  const ConstraintSetSpec spec = LoadConstraintConfig(path, fitting);
  CHECK_FALSE(spec.constraints[0].has_range);
  const auto skel = ShippedSkeleton("h36m").skeleton;
  CHECK_THROWS_WITH(ConstraintSet::Build(spec, *skel),
                    Catch::Contains(path) && Catch::Contains("missing range"));
  ConstraintBuildOptions no_ranges;
  no_ranges.require_ranges = false;
  const ConstraintSet set = ConstraintSet::Build(spec, *skel, no_ranges);
  CHECK_FALSE(set.constraint(0).has_range);
  CHECK(set.constraint(0).upper_deg == 180);
  CHECK_THROWS_WITH(LoadConstraintConfig(dir.file("missing.yaml")),
                    Catch::Contains("missing.yaml"));
  CHECK(ParseVectorExpression(" normal( bone(A,B) ,bone(B, C d) ) ").operands[1].to == "C d");
}
