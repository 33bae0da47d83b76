// Where the body goes (issue 27): the root and foot-skating figures on constructed motions, and the
// constant-velocity baseline that carries the root on.
#include "eval/root_motion.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "eval/baselines.h"
#include "test_support.h"

using namespace motionfork;

namespace {

constexpr UpAxis kYUp{1, 1};

// T frames of J joints, every joint at (x, y, z) = f(t, j).
template <typename F>
std::vector<float> Frames(int T, int J, F f) {
  std::vector<float> out;
  for (int t = 0; t < T; ++t)
    for (int j = 0; j < J; ++j)
      for (float v : f(t, j)) out.push_back(v);
  return out;
}

// The humanoid's first pose turned by `angle` about +Y through its root, the root at (x, h, z).
std::vector<float> Pose(const Motion& m, double angle, double x, double h, double z) {
  std::vector<float> out;
  const float* p = m.frame(0);
  const double c = std::cos(angle), s = std::sin(angle);
  for (int j = 0; j < m.num_joints(); ++j) {
    const double rx = p[3 * j] - p[0], ry = p[3 * j + 1] - p[1], rz = p[3 * j + 2] - p[2];
    // Turning (z, x) by +angle: the rotation the baseline applies in the plane of axes 2 and 0.
    const double nz = c * rz - s * rx, nx = s * rz + c * rx;
    out.insert(out.end(), {float(x + nx), float(h + ry), float(z + nz)});
  }
  return out;
}

}  // namespace

TEST_CASE("root figures: best-of-K root distance, spread of the last roots on the ground") {
  // Two samples of 2 frames, 2 joints; the truth's root at the origin then (1, 0, 0).
  const std::vector<float> truth = {0, 0, 0, 1, 0, 0};
  const std::vector<float> samples = {
      0, 0, 0, 9, 9, 9, /* frame 1 */ 1, 3, 0, 9, 9, 9,   // sample 0: last root 3 m too high
      0, 0, 1, 9, 9, 9, /* frame 1 */ 1, 0, 2, 9, 9, 9};  // sample 1: 1 m off, then 2 m
  const Displacement d = RootMinDisplacement(samples.data(), 2, 2, 2, truth.data());
  CHECK(d.ade == Approx(1.5));  // sample 0: (0 + 3) / 2; sample 1: (1 + 2) / 2
  CHECK(d.fde == Approx(2.0));
  // On the ground (x, z): the last roots (1, 0) and (1, 2): 2 m apart; the 3 m height is not seen.
  CHECK(FinalRootSpread(samples.data(), 2, 2, 2, kYUp) == Approx(2.0));
  CHECK(FinalRootSpread(samples.data(), 2, 2, 2, UpAxis{0, 1}) == Approx(std::hypot(3.0, 2.0)));
  CHECK_THROWS_WITH(FinalRootSpread(samples.data(), 1, 2, 2, kYUp), Catch::Contains("K >= 2"));
  CHECK_THROWS_WITH(RootMinDisplacement(samples.data(), 0, 2, 2, truth.data()),
                    Catch::Contains("got 0, 2, 2"));
}

TEST_CASE("foot skating: a planted foot scores 0, a sliding one its slide, a lifted one nothing") {
  // Joint 0 the root, joint 1 the foot; 5 frames; the root moves 10 cm a frame throughout.
  auto motion = [](double slide, double height) {
    return Frames(5, 2, [&](int t, int j) {
      if (j == 0) return std::vector<float>{float(0.1 * t), 1.0f, 0.0f};
      return std::vector<float>{float(slide * t), float(height), 0.0f};
    });
  };
  const std::vector<int> feet = {1};
  const std::vector<float> planted = motion(0, 0), sliding = motion(0.01, 0),
                           low = motion(0.01, 0.025), lifted = motion(0.01, 0.2);
  CHECK(GroundHeight(planted.data(), 5, 2, feet, kYUp) == 0.0);
  CHECK(FootSkating(planted.data(), 5, 2, feet, kYUp, 0.0, 0.05) == 0.0);
  CHECK(FootSkating(sliding.data(), 5, 2, feet, kYUp, 0.0, 0.05) == Approx(0.01));
  // Half the contact height up: weight 2 - sqrt(2).
  CHECK(FootSkating(low.data(), 5, 2, feet, kYUp, 0.0, 0.05) ==
        Approx(0.01 * (2 - std::sqrt(2.0))));
  CHECK(FootSkating(lifted.data(), 5, 2, feet, kYUp, 0.0, 0.05) == 0.0);
  // The ground is where the history's feet are: lifted 20 cm with the ground there, it slides.
  CHECK(FootSkating(lifted.data(), 5, 2, feet, kYUp, 0.2, 0.05) == Approx(0.01));
  CHECK_THROWS_WITH(FootSkating(planted.data(), 5, 2, {2}, kYUp, 0.0, 0.05),
                    Catch::Contains("foot joint 2 out of range, expected 0-1"));
  CHECK_THROWS_WITH(FootSkating(planted.data(), 1, 2, feet, kYUp, 0.0, 0.05),
                    Catch::Contains("2 frames"));
  CHECK_THROWS(FootSkating(planted.data(), 5, 2, feet, UpAxis{3, 1}, 0.0, 0.05));
}

TEST_CASE(
    "constant velocity: a straight walk goes on; with the turn, a turning walk along its curve") {
  const Motion m = testing::MakeWalkingMotion(1);
  const int J = m.num_joints(), his = 4, pred = 6;
  const double turn = 0.05, speed = 0.04;  // radians and metres a frame
  // A body turning at a constant rate, walking forward along its heading: frame t's root is the
  // sum of steps rotated by the heading so far.
  std::vector<float> motion;
  double x = 0, z = 0;
  for (int t = 0; t < his + pred; ++t) {
    if (t > 0) {
      z += speed * std::cos(turn * t);
      x += speed * std::sin(turn * t);
    }
    const std::vector<float> p = Pose(m, turn * t, x, 1.0 + 0.01 * t, z);
    motion.insert(motion.end(), p.begin(), p.end());
  }
  ConstantVelocityPredictor cv(m.skeleton_ptr(), his, pred, kYUp, {1, true});
  std::vector<float> futures;
  PredictRequest r;
  r.num_samples = 2;
  cv.Predict(std::vector<float>(motion.begin(), motion.begin() + his * J * 3), r, &futures);
  REQUIRE(futures.size() == 2u * pred * J * 3);
  const double last_height = 1.0 + 0.01 * (his - 1);
  double worst = 0;
  for (int t = 0; t < pred; ++t) {
    for (int j = 0; j < J; ++j) {
      for (int a = 0; a < 3; ++a) {
        const size_t i = (static_cast<size_t>(t) * J + j) * 3 + a;
        // The truth climbs 1 cm a frame; the baseline keeps the last height.
        const double want = motion[(static_cast<size_t>(his + t) * J + j) * 3 + a] -
                            (a == 1 ? 0.01 * (t + 1) : 0.0);
        worst = std::max(worst, std::abs(futures[i] - want));
        CHECK(futures[i] == futures[i + static_cast<size_t>(pred) * J * 3]);  // samples equal
      }
    }
    CHECK(futures[(static_cast<size_t>(t) * J) * 3 + 1] == Approx(last_height));
  }
  CHECK(worst < 1e-4);
  // The default: no turn, the velocity a mean over the whole history. The same body walking
  // straight along +Z goes on straight, at its speed, its pose unturned.
  std::vector<float> straight;
  for (int t = 0; t < his + pred; ++t) {
    const std::vector<float> p = Pose(m, 0.3, 0.0, 1.0, speed * t);
    straight.insert(straight.end(), p.begin(), p.end());
  }
  ConstantVelocityPredictor plain(m.skeleton_ptr(), his, pred, kYUp);
  CHECK(plain.description().find("velocity over the history's last 3 frame steps") !=
        std::string::npos);
  plain.Predict(std::vector<float>(straight.begin(), straight.begin() + his * J * 3), r, &futures);
  worst = 0;
  for (size_t i = 0; i < static_cast<size_t>(pred) * J * 3; ++i) {
    worst = std::max(worst, static_cast<double>(std::abs(futures[i] - straight[his * J * 3 + i])));
  }
  CHECK(worst < 1e-5);
  CHECK_THROWS_WITH(ConstantVelocityPredictor(m.skeleton_ptr(), his, pred, kYUp, {his, false}),
                    Catch::Contains("0 <= frames <= t_his - 1 (0: all), got t_his 4, frames 4"));
  CHECK_THROWS(ConstantVelocityPredictor(m.skeleton_ptr(), his, pred, UpAxis{1, 0}));
}
