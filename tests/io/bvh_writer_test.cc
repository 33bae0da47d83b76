// BVH writing: positions -> BVH -> ReadMotionFile round trips (rigid bones, varying bones, units,
// skeleton orders), the file's layout, Euler angles (every order, continuity, gimbal lock) and
// errors that leave no file behind.
#include "io/bvh_writer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/limbs.h"
#include "core/pose_fixtures.h"
#include "io/bvh.h"
#include "io/file_util.h"
#include "io/motion_file.h"
#include "test_support.h"

namespace motionfork {
namespace {

Motion ReadBack(const std::string& path, double scale_to_metres = 0.01) {
  MotionReadOptions o;
  o.bvh.scale_to_metres = scale_to_metres;
  return ReadMotionFile(path, o);
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// R_order[0](a) R_order[1](b) R_order[2](c), angles in degrees.
Eigen::Matrix3d Compose(const std::string& order, const std::array<double, 3>& deg) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  for (int n = 0; n < 3; ++n) {
    r = r * Eigen::AngleAxisd(deg[n] * M_PI / 180, Eigen::Vector3d::Unit(order[n] - 'X'))
                .toRotationMatrix();
  }
  return r;
}

TEST_CASE("bvh writer: a motion with rigid bones round trips through ReadMotionFile") {
  const testing::RotatedMotion rm = testing::MakeRotatedMotion(120, 9, 75, 150);
  testing::TempDir dir;
  for (const double scale : {0.01, 1.0}) {
    for (const char* order : {"ZXY", "ZYX", "XYZ"}) {
      BvhWriteOptions o;
      o.scale_to_metres = scale;
      o.rotation_order = order;
      const std::string path = dir.file(std::string("rigid_") + order + ".bvh");
      WriteBvh(path, rm.motion, o);
      const Motion back = ReadBack(path, scale);
      REQUIRE(back.skeleton().SameStructure(rm.motion.skeleton()));
      CHECK(back.fps() == 30.0);
      const double err = testing::MaxDistance(back, rm.motion);
      INFO("scale " << scale << ", order " << order << ": max round-trip error " << err << " m");
      CHECK(err < 1e-4);
      CHECK(err < 5e-6);  // what the writer actually achieves (6 decimals, float positions)
    }
  }
}

TEST_CASE("bvh writer: file layout (channels, End Sites, joint order, frame time)") {
  const testing::RotatedMotion rm = testing::MakeRotatedMotion(4);
  const std::vector<std::string> lines = Lines(BvhText(rm.motion));
  REQUIRE(lines.size() > 10);
  CHECK(lines[0] == "HIERARCHY");
  CHECK(lines[1] == "ROOT Hips");
  int joints = 0, end_sites = 0, six = 0, three = 0;
  std::vector<std::string> names;
  for (const std::string& l : lines) {
    const std::string s =
        l.substr(l.find_first_not_of(' ') == std::string::npos ? 0 : l.find_first_not_of(' '));
    if (s.rfind("ROOT ", 0) == 0 || s.rfind("JOINT ", 0) == 0)
      names.push_back(s.substr(s.find(' ') + 1));
    if (s == "End Site") ++end_sites;
    if (s == "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation") ++six;
    if (s == "CHANNELS 3 Zrotation Xrotation Yrotation") ++three;
  }
  joints = static_cast<int>(names.size());
  CHECK(joints == 17);
  CHECK(names == rm.motion.skeleton().joint_names());  // depth-first already: same order
  CHECK(end_sites == 5);                               // feet, head, hands
  CHECK(six == 1);                                     // the root: rigid bones need no translations
  CHECK(three == 16);
  const auto motion = std::find(lines.begin(), lines.end(), "MOTION");
  REQUIRE(motion != lines.end());
  CHECK(motion[1] == "Frames: 4");
  CHECK(motion[2] == "Frame Time: 0.03333333333");
  CHECK(lines.end() - motion == 3 + 4);
}

TEST_CASE(
    "bvh writer: varying bone lengths: exact positions by default, directions at the mean lengths "
    "with kMean") {
  // A predicted future: every bone's length wobbles and the chest's children move against each
  // other.
  const Motion m = testing::MakeWalkingMotion(60);
  testing::TempDir dir;
  WriteMotionFile(dir.file("exact.bvh"), m);
  CHECK(testing::MaxDistance(ReadBack(dir.file("exact.bvh")), m) < 2e-6);

  BvhWriteOptions o;
  o.fit.lengths = BoneLengths::kMean;
  WriteMotionFile(dir.file("future.bvh"), m, o);
  const Motion back = ReadBack(dir.file("future.bvh"));
  REQUIRE(back.skeleton().SameStructure(m.skeleton()));
  const testing::MeanLengthDeviation d = testing::DeviationFromMeanLengths(m, back);
  INFO("largest direction component error " << d.direction << ", length error " << d.length
                                            << " m");
  CHECK(d.length < 2e-6);
  CHECK(d.direction < 2e-5);
  CHECK(testing::MaxDistance(back, m) > 0.01);  // the lengths did vary
  // The root is where the input has it.
  for (int t = 0; t < 60; ++t) {
    for (int a = 0; a < 3; ++a) CHECK(back.at(t, 0)[a] == Approx(m.at(t, 0)[a]).margin(1e-6));
  }
}

TEST_CASE("bvh writer: a skeleton not in depth-first order is written depth-first") {
  // Joints: root, a, b, a1 (child of a), b1 (child of b): the file order is root a a1 b b1.
  const auto skel = std::make_shared<const Skeleton>(
      Skeleton::FromParents("fork", {"root", "a", "b", "a1", "b1"}, {-1, 0, 0, 1, 2}));
  std::mt19937 rng(4);
  std::normal_distribution<float> noise(0, 0.01f);
  std::vector<float> p;
  for (int t = 0; t < 20; ++t) {
    const float base[5][3] = {
        {0, 1, 0}, {0.2f, 1, 0}, {-0.2f, 1, 0}, {0.2f, 0.6f, 0}, {-0.2f, 0.6f, 0.1f}};
    for (const auto& j : base) {
      for (float v : j) p.push_back(v + noise(rng));
    }
  }
  const Motion m(skel, 25, p);
  testing::TempDir dir;
  WriteBvh(dir.file("fork.bvh"), m);
  const Motion back = ReadBack(dir.file("fork.bvh"));
  CHECK(back.skeleton().joint_names() == std::vector<std::string>{"root", "a", "a1", "b", "b1"});
  CHECK(back.fps() == 25.0);
  const Limbs in = ToLimbs(m);
  for (int t = 0; t < 20; ++t) {
    for (int j = 0; j < 5; ++j) {
      const int k = back.skeleton().Index(skel->joint_name(j));
      if (j == 0) {
        for (int a = 0; a < 3; ++a) CHECK(back.at(t, k)[a] == Approx(m.at(t, j)[a]).margin(1e-6));
        continue;
      }
      const int pk = back.skeleton().parent(k);
      for (int a = 0; a < 3; ++a) {
        const double len = std::sqrt(std::pow(back.at(t, k)[0] - back.at(t, pk)[0], 2) +
                                     std::pow(back.at(t, k)[1] - back.at(t, pk)[1], 2) +
                                     std::pow(back.at(t, k)[2] - back.at(t, pk)[2], 2));
        CHECK((back.at(t, k)[a] - back.at(t, pk)[a]) / len ==
              Approx(in.directions[(t * 4 + j - 1) * 3 + a]).margin(1e-5));
      }
    }
  }
}

TEST_CASE(
    "bvh writer: Euler angles compose back for every order, stay continuous, survive gimbal lock") {
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  for (const std::string order : {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"}) {
    for (int n = 0; n < 50; ++n) {
      const Eigen::Matrix3d r =
          Eigen::AngleAxisd(3 * normal(rng),
                            Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized())
              .toRotationMatrix();
      const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> row = r;
      const std::array<double, 3> e = EulerDegrees(row.data(), order);
      INFO(order << " " << e[0] << " " << e[1] << " " << e[2]);
      CHECK((Compose(order, e) - r).norm() < 1e-9);
      for (double angle : e) CHECK(std::abs(angle) <= 180.0 + 1e-9);  // unwrapped towards 0
    }
  }
  SECTION("continuity: a steady turn past 180 degrees unwraps") {
    std::array<double, 3> prev = {0, 0, 0};
    for (int step = 0; step <= 40; ++step) {
      const std::array<double, 3> want = {10.0 * step, 20, -5};
      const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> row = Compose("ZXY", want);
      prev = EulerDegrees(row.data(), "ZXY", prev);
      CHECK(prev[0] == Approx(want[0]).margin(1e-6));
      CHECK(prev[1] == Approx(want[1]).margin(1e-6));
      CHECK(prev[2] == Approx(want[2]).margin(1e-6));
    }
  }
  SECTION("continuity: past +90 degrees of the middle angle, the second solution") {
    // b goes 80 -> 100: the principal solution would flip a and c by 180 degrees.
    std::array<double, 3> prev = {30, 80, 10};
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> row = Compose("ZXY", {30, 100, 10});
    prev = EulerDegrees(row.data(), "ZXY", prev);
    CHECK(prev[0] == Approx(30).margin(1e-6));
    CHECK(prev[1] == Approx(100).margin(1e-6));
    CHECK(prev[2] == Approx(10).margin(1e-6));
  }
  SECTION("gimbal lock keeps the first angle") {
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> row = Compose("ZXY", {40, 90, 25});
    const std::array<double, 3> e = EulerDegrees(row.data(), "ZXY", {12, 88, 0});
    CHECK(e[0] == Approx(12).margin(1e-9));
    CHECK(e[1] == Approx(90).margin(1e-6));
    CHECK((Compose("ZXY", e) - Compose("ZXY", {40, 90, 25})).norm() < 1e-9);
  }
  const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  CHECK_THROWS_WITH(EulerDegrees(identity, "ZZY"),
                    Catch::Contains("expected a permutation of XYZ (e.g. ZXY), got 'ZZY'"));
}

TEST_CASE("bvh writer: bad input gives a clear error and leaves no file") {
  testing::TempDir dir;
  const Motion walk = testing::MakeWalkingMotion(10);
  const std::string out = dir.file("out.bvh");
  SECTION("anonymous or unlinked skeleton") {
    const auto anon = std::make_shared<const Skeleton>(Skeleton::Anonymous(17));
    CHECK_THROWS_WITH(WriteBvh(out, Motion(anon, 30, walk.positions())),
                      Catch::Contains("no limb structure"));
    const auto unlinked =
        std::make_shared<const Skeleton>(Skeleton::Unlinked("csv", walk.skeleton().joint_names()));
    CHECK_THROWS_WITH(WriteBvh(out, Motion(unlinked, 30, walk.positions())),
                      Catch::Contains("'csv' has no limb structure"));
    CHECK_FALSE(std::filesystem::exists(out));
  }
  SECTION("a zero-length bone names the frame") {
    std::vector<float> p = walk.positions();
    for (int a = 0; a < 3; ++a) p[(4 * 17 + 13) * 3 + a] = p[(4 * 17 + 12) * 3 + a];
    CHECK_THROWS_WITH(WriteBvh(out, Motion(walk.skeleton_ptr(), 30, p)),
                      Catch::Contains("frame 4: bone 'LowerArm_L' -> 'Hand_L'"));
    CHECK_FALSE(std::filesystem::exists(out));
  }
  SECTION("a joint name BVH cannot hold") {
    const auto spaced = std::make_shared<const Skeleton>(
        Skeleton::FromParents("s", {"pelvis", "left hip"}, {-1, 0}));
    CHECK_THROWS_WITH(WriteBvh(out, Motion(spaced, 30, {0, 1, 0, 0.1f, 0.9f, 0})),
                      Catch::Contains("joint 1 'left hip': expected a BVH joint name"));
    CHECK_FALSE(std::filesystem::exists(out));
  }
  SECTION("bad options") {
    BvhWriteOptions o;
    o.scale_to_metres = 0;
    CHECK_THROWS_WITH(WriteBvh(out, walk, o),
                      Catch::Contains("scale_to_metres: expected a finite number > 0"));
    o = {};
    o.rotation_order = "XY";
    CHECK_THROWS_WITH(WriteBvh(out, walk, o), Catch::Contains("rotation_order"));
    o = {};
    o.decimals = 0;
    CHECK_THROWS_WITH(WriteBvh(out, walk, o), Catch::Contains("decimals: expected 1..15, got 0"));
    CHECK_FALSE(std::filesystem::exists(out));
  }
  SECTION("an unwritable path (under a regular file)") {
    std::ofstream(dir.file("plain")) << "x";
    CHECK_THROWS_AS(WriteBvh(dir.file("plain/out.bvh"), walk), FormatError);
    CHECK_THROWS_WITH(WriteBvh(dir.file("plain/out.bvh"), walk), Catch::Contains("plain/out.bvh"));
    CHECK(std::distance(std::filesystem::directory_iterator(dir.path()), {}) == 1);
  }
  SECTION("a failed write keeps the previous file") {
    WriteBvh(out, walk);
    const std::string before = ReadFileBytes(out);
    const auto anon = std::make_shared<const Skeleton>(Skeleton::Anonymous(17));
    CHECK_THROWS(WriteMotionFile(out, Motion(anon, 30, walk.positions())));
    CHECK(ReadFileBytes(out) == before);
    CHECK(std::distance(std::filesystem::directory_iterator(dir.path()), {}) == 1);  // no temp left
  }
}

}  // namespace
}  // namespace motionfork
