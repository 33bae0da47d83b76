// Unit, up axis and left/right of a motion told from the body, and the way back.
#include "rig/body_frame.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "config/config_paths.h"
#include "config/rig_config.h"
#include "config/skeleton_config.h"
#include "core/demo_motion.h"
#include "rig/joint_mapping.h"

using namespace motionfork;

namespace {

struct Fixture {
  std::shared_ptr<const Skeleton> skeleton =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "bandai")).skeleton;
  std::vector<std::string> roles =
      RolesOfSkeleton(*skeleton, LoadRigConventions(MOTIONFORK_CONFIG_DIR)).roles;
  Motion Walk(double heading = 0, double speed = 1.2) const {
    DemoWalkOptions o;
    o.frames = 90;
    o.heading_deg = heading;
    o.speed = speed;
    return MakeDemoWalk(skeleton, o);
  }
};

double MaxDifference(const Motion& a, const Motion& b) {
  double d = 0;
  for (size_t i = 0; i < a.positions().size(); ++i)
    d = std::max(d, std::abs(static_cast<double>(a.positions()[i]) - b.positions()[i]));
  return d;
}

}  // namespace

TEST_CASE("a walk in metres, Y up, labelled right is read as it is") {
  const Fixture f;
  const BodyFrame frame = DetectBodyFrame(f.Walk(), {}, f.roles, {});
  CHECK(frame.unit_detected);
  CHECK(frame.unit == 1.0);
  CHECK(frame.up_detected);
  CHECK(frame.up_axis == 1);
  CHECK(frame.up_sign == 1);
  CHECK(frame.left_right_detected);
  CHECK_FALSE(frame.swapped);
  CHECK(frame.IsIdentity(1.0));
  CHECK(frame.warnings.empty());
  CHECK(frame.body_size == Approx(1.3).margin(0.3));
}

TEST_CASE("every unit, up axis and mirrored labels are detected and undone") {
  const Fixture f;
  struct Case {
    double unit;
    int axis, sign;
    bool swapped;
    double heading;
  };
  const std::vector<Case> cases = {
      {0.01, 2, 1, false, 0},    {0.001, 1, 1, true, 40}, {0.0254, 2, -1, false, 200},
      {1.0, 1, -1, false, 90},   {0.01, 0, 1, true, 300}, {0.001, 0, -1, false, 135},
      {0.0254, 1, 1, true, 250}, {1.0, 2, 1, true, 10},
  };
  for (const Case& c : cases) {
    const Motion walk = f.Walk(c.heading);
    BodyFrame truth;
    truth.unit = truth.scale = c.unit;
    truth.up_axis = c.axis;
    truth.up_sign = c.sign;
    truth.swapped = c.swapped;
    const Motion file = FromModelFrame(walk, truth, f.roles);
    INFO("unit " << c.unit << " up " << c.sign << "*" << c.axis << " swapped " << c.swapped
                 << " heading " << c.heading);
    const BodyFrame got = DetectBodyFrame(file, {}, f.roles, {});
    CHECK(got.unit == Approx(c.unit));
    CHECK(got.up_axis == c.axis);
    CHECK(got.up_sign == c.sign);
    CHECK(got.swapped == c.swapped);
    CHECK(MaxDifference(ToModelFrame(file, got, f.roles, nullptr), walk) < 1e-5);
    // Upside down and mirrored are doubts, said as warnings; Z up or centimetres are not.
    const bool doubtful = c.swapped || (c.axis == 1 && c.sign < 0);
    CHECK(got.warnings.empty() == !doubtful);
  }
}

TEST_CASE("a BVH read as centimetres: the unit named as the file's; forced values win") {
  const Fixture f;
  const Motion walk = f.Walk();
  // A file in millimetres read with 0.01 m per unit: values 10x the metres.
  BodyFrame read_as_cm;
  read_as_cm.scale = 0.1;
  const Motion file = FromModelFrame(walk, read_as_cm, f.roles);
  BodyFrameOptions o;
  o.read_scale = 0.01;
  const BodyFrame got = DetectBodyFrame(file, {}, f.roles, o);
  CHECK(got.unit == Approx(0.001));
  CHECK(got.scale == Approx(0.1));
  CHECK(got.Describe() == "millimetres, Y up");
  o.unit = 0.01;  // forced: kept, even though the body is then 10x too large
  o.up = "z";
  o.left_right = "swapped";
  const BodyFrame forced = DetectBodyFrame(file, {}, f.roles, o);
  CHECK_FALSE(forced.unit_detected);
  CHECK(forced.scale == Approx(1.0));
  CHECK(forced.body_size == Approx(13).margin(4));
  CHECK(forced.up_axis == 2);
  CHECK(forced.swapped);
  o.up = "w";
  CHECK_THROWS_WITH(DetectBodyFrame(file, {}, f.roles, o), Catch::Contains("expected auto, y"));
  CHECK_THROWS_WITH(ParseLengthUnit("ft"), Catch::Contains("expected auto, m, cm, mm or in"));
}

TEST_CASE("a body of no human size in any unit is kept as read, with a warning") {
  const Fixture f;
  BodyFrame odd;
  odd.unit = odd.scale = 0.2;  // 20 cm units: 6.6 units, 660 cm, 6,600 mm, 260 in
  const Motion file = FromModelFrame(f.Walk(), odd, f.roles);
  const BodyFrame got = DetectBodyFrame(file, {}, f.roles, {});
  CHECK_FALSE(got.unit_detected);
  CHECK(got.scale == 1.0);
  REQUIRE_FALSE(got.warnings.empty());
  CHECK_THAT(got.warnings[0],
             Catch::Contains("in none of m, cm, mm, in") && Catch::Contains("--unit"));
}

TEST_CASE("missing values are left out of the evidence and follow the left/right exchange") {
  const Fixture f;
  const Motion walk = f.Walk();
  BodyFrame swapped;
  swapped.swapped = true;
  const Motion file = FromModelFrame(walk, swapped, f.roles);
  std::vector<uint8_t> missing(file.positions().size(), 0);
  const int knee_l = f.skeleton->Index("LowerLeg_L"), knee_r = f.skeleton->Index("LowerLeg_R");
  for (int t = 0; t < 30; ++t) missing[(static_cast<size_t>(t) * 17 + knee_l) * 3] = 1;
  const BodyFrame got = DetectBodyFrame(file, missing, f.roles, {});
  CHECK(got.swapped);
  const Motion back = ToModelFrame(file, got, f.roles, &missing);
  CHECK(missing[static_cast<size_t>(knee_r) * 3] == 1);
  CHECK(missing[static_cast<size_t>(knee_l) * 3] == 0);
  CHECK(MaxDifference(back, walk) < 1e-5);
}
