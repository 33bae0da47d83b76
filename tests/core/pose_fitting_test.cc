// Positions -> rotations: forward kinematics of the fit against the input, the rotations against
// the ones a motion was built from, least squares at branching joints, varied bone lengths, errors.
#include "core/pose_fitting.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/limbs.h"
#include "core/pose_fixtures.h"
#include "test_support.h"

namespace motionfork {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

Matrix3d LocalRotation(const PoseFit& fit, int t, int j) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(fit.rotation(t, j));
}

// World rotation of joint j in frame t: the product of the local ones from the root.
Matrix3d WorldRotation(const PoseFit& fit, const Skeleton& s, int t, int j) {
  return j < 0 ? Matrix3d::Identity()
               : Matrix3d(WorldRotation(fit, s, t, s.parent(j)) * LocalRotation(fit, t, j));
}

int CountTranslated(const PoseFit& fit) {
  int n = 0;
  for (bool b : fit.translated) n += b;
  return n;
}

TEST_CASE("pose fit: a motion with rigid bones is reproduced by rotations alone") {
  const testing::RotatedMotion rm = testing::MakeRotatedMotion(90);
  const PoseFit fit = FitPose(rm.motion);
  REQUIRE(fit.num_frames == 90);
  REQUIRE(fit.num_joints == 17);
  CHECK(CountTranslated(fit) == 1);  // the root only: hips and chest move rigidly
  const Motion back = PoseFitPositions(fit, rm.motion.skeleton_ptr(), rm.motion.fps());
  const double err = testing::MaxDistance(back, rm.motion);
  INFO("max FK error " << err << " m");
  CHECK(err < 2e-6);
  // Every local rotation is a proper rotation.
  for (int t = 0; t < 90; t += 7) {
    for (int j = 0; j < 17; ++j) {
      const Matrix3d r = LocalRotation(fit, t, j);
      CHECK((r * r.transpose() - Matrix3d::Identity()).norm() < 1e-9);
      CHECK(r.determinant() == Approx(1.0).margin(1e-9));
    }
  }
}

TEST_CASE("pose fit: branching joints recover the rotations the motion was built with") {
  // The rest pose is an average pose, not the builder's, so compare rotations between frames:
  // W(t) W(0)^T is the same whatever the rest.
  const testing::RotatedMotion rm = testing::MakeRotatedMotion(60, 11);
  const Skeleton& s = rm.motion.skeleton();
  const PoseFit fit = FitPose(rm.motion);
  for (const char* name : {"Hips", "Chest"}) {
    const int j = s.Index(name);
    REQUIRE(s.Subtree(j).size() > 3);  // several children
    for (int t = 0; t < 60; t += 5) {
      const Matrix3d want = rm.world[t * 17 + j] * rm.world[j].transpose();
      const Matrix3d got = WorldRotation(fit, s, t, j) * WorldRotation(fit, s, 0, j).transpose();
      INFO(name << " frame " << t);
      CHECK((want - got).norm() < 1e-5);
    }
  }
}

TEST_CASE(
    "pose fit: a branching joint whose children move against each other gets the least-squares "
    "rotation") {
  // Shrug: the upper arms move against the neck, so no rotation of the chest fits all three.
  testing::RotatedMotion rm = testing::MakeRotatedMotion(40, 5);
  const Skeleton& s = rm.motion.skeleton();
  // Each arm turns about the chest joint on its own, so every bone keeps its length.
  const int chest = s.Index("Chest");
  std::vector<float> p = rm.motion.positions();
  for (int t = 0; t < 40; ++t) {
    const Vector3d centre(rm.motion.at(t, chest)[0], rm.motion.at(t, chest)[1],
                          rm.motion.at(t, chest)[2]);
    for (const auto& [arm, turn] :
         {std::make_pair("UpperArm_L",
                         Eigen::AngleAxisd(0.3 * std::sin(0.3 * t), Vector3d::UnitZ())),
          std::make_pair("UpperArm_R",
                         Eigen::AngleAxisd(0.2 * std::cos(0.2 * t), Vector3d::UnitY()))}) {
      for (int j : s.Subtree(s.Index(arm))) {
        float* q = &p[(t * 17 + j) * 3];
        const Vector3d moved = centre + turn * (Vector3d(q[0], q[1], q[2]) - centre);
        for (int a = 0; a < 3; ++a) q[a] = static_cast<float>(moved[a]);
      }
    }
  }
  const Motion shrug(rm.motion.skeleton_ptr(), 30, p);
  const PoseFit fit = FitPose(shrug);
  // The chest's children are translated: positions exact, lengths their means.
  for (const char* child : {"Neck", "UpperArm_L", "UpperArm_R"})
    CHECK(fit.translated[s.Index(child)]);
  CHECK(CountTranslated(fit) == 4);
  const Limbs in = ToLimbs(shrug);
  const Limbs out = ToLimbs(PoseFitPositions(fit, shrug.skeleton_ptr(), 30));
  for (size_t i = 0; i < in.directions.size(); ++i)
    REQUIRE(out.directions[i] == Approx(in.directions[i]).margin(1e-5));
  // Local optimality: turning the chest a little either way about any axis fits worse.
  std::vector<int> children;
  for (int j = 0; j < 17; ++j) {
    if (s.parent(j) == chest) children.push_back(j);
  }
  auto misfit = [&](const Matrix3d& w, int t) {
    double sum = 0;
    for (int c : children) {
      const Vector3d rest = Eigen::Map<const Vector3d>(&fit.offsets[3 * c]);
      const Vector3d dir(in.directions[3 * (t * 16 + c - 1)],
                         in.directions[3 * (t * 16 + c - 1) + 1],
                         in.directions[3 * (t * 16 + c - 1) + 2]);
      sum += rest.norm() * (w * rest.normalized() - dir).squaredNorm();
    }
    return sum;
  };
  for (int t = 0; t < 40; t += 3) {
    const Matrix3d w = WorldRotation(fit, s, t, chest);
    const double best = misfit(w, t);
    CHECK(best > 1e-6);  // there is a misfit to minimise
    for (int axis = 0; axis < 3; ++axis) {
      for (double step : {-1e-3, 1e-3}) {
        const Matrix3d turned =
            Eigen::AngleAxisd(step, Vector3d::Unit(axis)).toRotationMatrix() * w;
        CHECK(misfit(turned, t) > best);
      }
    }
  }
  SECTION("tolerance < 0: rotations only, the misfit stays") {
    PoseFitOptions o;
    o.tolerance = -1;
    const PoseFit rot = FitPose(shrug, o);
    CHECK(CountTranslated(rot) == 1);
    const double err = testing::MaxDistance(PoseFitPositions(rot, shrug.skeleton_ptr(), 30), shrug);
    CHECK(err > 1e-3);
    CHECK(err < 0.1);
  }
  SECTION("kMean: the same, the shrug's bones keep their lengths") {
    PoseFitOptions o;
    o.lengths = BoneLengths::kMean;
    const PoseFit mean = FitPose(shrug, o);
    CHECK(mean.translated == fit.translated);
    CHECK(testing::MaxDistance(PoseFitPositions(mean, shrug.skeleton_ptr(), 30), shrug) < 1e-5);
  }
}

TEST_CASE("pose fit: kMean reproduces varying bone lengths as directions at the mean lengths") {
  // MakeWalkingMotion wobbles every offset, as a predicted future does.
  const Motion m = testing::MakeWalkingMotion(50);
  PoseFitOptions o;
  o.lengths = BoneLengths::kMean;
  const PoseFit fit = FitPose(m, o);
  const testing::MeanLengthDeviation d =
      testing::DeviationFromMeanLengths(m, PoseFitPositions(fit, m.skeleton_ptr(), m.fps()));
  CHECK(d.length < 1e-6);
  CHECK(d.direction < 1e-5);
  const Limbs in = ToLimbs(m);
  CHECK(in.lengths[0] != Approx(in.lengths[16 * 20]).margin(1e-4));  // the lengths did vary
}

TEST_CASE("pose fit: kExact translates the bones whose length varies, and only those") {
  SECTION("every bone wobbles: all translated, positions exact") {
    const Motion m = testing::MakeWalkingMotion(50);
    const PoseFit fit = FitPose(m);
    CHECK(CountTranslated(fit) == 17);
    CHECK(testing::MaxDistance(PoseFitPositions(fit, m.skeleton_ptr(), 30), m) < 1e-6);
  }
  SECTION("a ground-level root the hips walk away from (Bandai's joint_Root)") {
    // floor -> the humanoid's joints; the floor joint stays at the origin, so floor -> Hips is no
    // bone. It must not steer the floor's rotation, and every other bone keeps its rotations.
    const testing::RotatedMotion rm = testing::MakeRotatedMotion(60, 2);
    const Skeleton& h = rm.motion.skeleton();
    std::vector<std::string> names = {"floor"};
    std::vector<int> parents = {-1};
    for (int j = 0; j < 17; ++j) {
      names.push_back(h.joint_name(j));
      parents.push_back(h.parent(j) + 1);
    }
    const auto skel =
        std::make_shared<const Skeleton>(Skeleton::FromParents("floored", names, parents));
    std::vector<float> p;
    for (int t = 0; t < 60; ++t) {
      p.insert(p.end(), {0, 0, 0});
      p.insert(p.end(), rm.motion.frame(t), rm.motion.frame(t) + 17 * 3);
    }
    const Motion m(skel, 30, p);
    const PoseFit fit = FitPose(m);
    CHECK(CountTranslated(fit) == 2);  // floor and Hips
    CHECK(fit.translated[1]);
    for (int t = 0; t < 60; t += 9) CHECK(LocalRotation(fit, t, 0).isIdentity(1e-12));
    CHECK(testing::MaxDistance(PoseFitPositions(fit, skel, 30), m) < 2e-6);
  }
}

TEST_CASE("pose fit: clear errors") {
  const Motion walk = testing::MakeWalkingMotion(10);
  SECTION("no limb structure") {
    const auto anon = std::make_shared<const Skeleton>(Skeleton::Anonymous(17));
    CHECK_THROWS_WITH(FitPose(Motion(anon, 30, walk.positions())),
                      Catch::Contains("no limb structure") &&
                          Catch::Contains("expected a skeleton with parents"));
    const auto unlinked = std::make_shared<const Skeleton>(
        Skeleton::Unlinked("from_csv", walk.skeleton().joint_names()));
    CHECK_THROWS_WITH(FitPose(Motion(unlinked, 30, walk.positions())),
                      Catch::Contains("'from_csv' has no limb structure"));
  }
  SECTION("a bone of zero length names the frame and the bone") {
    std::vector<float> p = walk.positions();
    for (int a = 0; a < 3; ++a)
      p[(7 * 17 + 2) * 3 + a] = p[(7 * 17 + 1) * 3 + a];  // LowerLeg_R on UpperLeg_R
    CHECK_THROWS_WITH(FitPose(Motion(walk.skeleton_ptr(), 30, p)),
                      Catch::StartsWith("FitPose: frame 7: bone 'UpperLeg_R' -> 'LowerLeg_R'"));
  }
  SECTION("one joint, no frames, bad options") {
    const auto one = std::make_shared<const Skeleton>(Skeleton::FromParents("dot", {"a"}, {-1}));
    CHECK_THROWS_WITH(FitPose(Motion(one, 30, {0, 0, 0})), Catch::Contains("at least 2 joints"));
    CHECK_THROWS_WITH(FitPose(Motion(walk.skeleton_ptr(), 30, {})),
                      Catch::Contains("expected at least 1 frame"));
    PoseFitOptions o;
    o.min_bone_length = 0;
    CHECK_THROWS_WITH(FitPose(walk, o), Catch::Contains("min_bone_length"));
  }
}

}  // namespace
}  // namespace motionfork
