// The classical fills a learned imputer is measured against (no LibTorch).
#include "imputation/interpolation_fill.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "imputation/refiner_fills.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;

namespace {

// Missing: joint j's three coordinates in frames [first, last].
void Hide(std::vector<uint8_t>* mask, int joints, int j, int first, int last) {
  for (int t = first; t <= last; ++t)
    for (int a = 0; a < 3; ++a) (*mask)[(static_cast<size_t>(t) * joints + j) * 3 + a] = 1;
}

// Largest |a - b| over the masked values.
double WorstMissing(const std::vector<float>& a, const std::vector<float>& b,
                    const std::vector<uint8_t>& mask) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i)
    if (mask[i]) worst = std::max(worst, std::abs(double(a[i]) - b[i]));
  return worst;
}

}  // namespace

TEST_CASE("interpolation fills straight-line motion exactly, keeps observed values, holds ends") {
  // Two joints: the root walks in a straight line, the other moves linearly relative to it.
  const int T = 30, J = 2;
  std::vector<float> p;
  for (int t = 0; t < T; ++t)
    p.insert(p.end(), {0.1f * t, 1.0f, -0.05f * t, 0.1f * t + 0.3f, 1.0f - 0.01f * t, -0.05f * t});
  std::vector<uint8_t> mask(p.size(), 0);
  Hide(&mask, J, 1, 5, 17);
  Hide(&mask, J, 0, 9, 11);
  std::vector<float> damaged = p;
  for (size_t i = 0; i < p.size(); ++i)
    if (mask[i]) damaged[i] = NAN;
  for (Interpolation kind : {Interpolation::kLinear, Interpolation::kCubicSpline}) {
    const std::vector<float> out = InterpolateMissing(damaged, mask, J, kind);
    CHECK(WorstMissing(out, p, mask) < 1e-5);
    for (size_t i = 0; i < p.size(); ++i)
      if (!mask[i]) CHECK(out[i] == damaged[i]);
  }
  // Beyond the last observed frame: the nearest value (relative to the root).
  std::vector<uint8_t> tail(p.size(), 0);
  Hide(&tail, J, 1, 25, 29);
  const std::vector<float> held = InterpolateMissing(p, tail, J, Interpolation::kLinear);
  CHECK(held[(29 * J + 1) * 3 + 1] == Approx(p[(24 * J + 1) * 3 + 1]));
  CHECK(held[(29 * J + 1) * 3] == Approx(p[29 * J * 3] + 0.3f));  // moves with the root
}

TEST_CASE("a cubic spline beats straight lines on smooth motion with gaps") {
  const Motion m = testing::MakeWalkingMotion(90);
  const int J = m.num_joints();
  std::vector<uint8_t> mask(m.positions().size(), 0);
  std::mt19937 rng(5);
  for (int j = 1; j < J; ++j) Hide(&mask, J, j, 10 + int(rng() % 50), 10 + int(rng() % 50) + 4);
  const std::vector<float> lin = InterpolateMissing(m.positions(), mask, J, Interpolation::kLinear);
  const std::vector<float> spl =
      InterpolateMissing(m.positions(), mask, J, Interpolation::kCubicSpline);
  double se_lin = 0, se_spl = 0;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    se_lin += std::pow(lin[i] - m.positions()[i], 2);
    se_spl += std::pow(spl[i] - m.positions()[i], 2);
  }
  INFO("squared error: linear " << se_lin << ", spline " << se_spl);
  CHECK(se_spl < se_lin);
  CHECK(se_lin > 0);
}

TEST_CASE("a joint missing in every frame needs a fallback pose, named otherwise") {
  const Motion m = testing::MakeWalkingMotion(12);
  const int J = m.num_joints();
  std::vector<uint8_t> mask(m.positions().size(), 0);
  Hide(&mask, J, 4, 0, 11);
  CHECK_THROWS_WITH(InterpolateMissing(m.positions(), mask, J, Interpolation::kLinear),
                    Contains("joint 4") && Contains("every frame"));
  CHECK_THROWS_WITH(RigidLimbFill(m.skeleton(), m.positions(), mask), Contains("joint 4"));
  std::vector<float> fallback(static_cast<size_t>(J) * 3, 0.0f);
  fallback[4 * 3 + 1] = 0.5f;
  const std::vector<float> out =
      InterpolateMissing(m.positions(), mask, J, Interpolation::kLinear, fallback);
  for (int t = 0; t < 12; ++t) {
    CHECK(out[(t * J + 4) * 3 + 1] == Approx(m.positions()[t * J * 3 + 1] + 0.5f));
  }
  CHECK_THROWS_WITH(
      InterpolateMissing(m.positions(), std::vector<uint8_t>(5), J, Interpolation::kLinear),
      Contains("mask"));
}

TEST_CASE("rigid-limb fill keeps bone lengths and turns the bone between observed frames") {
  const Motion m = testing::MakeWalkingMotion(60);
  const Skeleton& sk = m.skeleton();
  const int J = sk.num_joints();
  std::vector<uint8_t> mask(m.positions().size(), 0);
  int leaf = J - 1;  // a joint with a parent other than the root
  REQUIRE(sk.parent(leaf) > 0);
  Hide(&mask, J, leaf, 20, 40);
  Hide(&mask, J, sk.parent(leaf), 25, 35);
  const std::vector<float> out = RigidLimbFill(sk, m.positions(), mask);
  auto bone = [&](const std::vector<float>& p, int t, int j) {
    double s = 0;
    for (int a = 0; a < 3; ++a) {
      const double d = p[(t * J + j) * 3 + a] - p[(t * J + sk.parent(j)) * 3 + a];
      s += d * d;
    }
    return std::sqrt(s);
  };
  // The bone's median length over the frames where both its ends are observed.
  std::vector<double> observed;
  for (int t = 0; t < 60; ++t)
    if (t < 20 || t > 40) observed.push_back(bone(m.positions(), t, leaf));
  std::nth_element(observed.begin(), observed.begin() + observed.size() / 2, observed.end());
  for (int t = 20; t <= 40; ++t) {
    CHECK(bone(out, t, leaf) == Approx(observed[observed.size() / 2]).epsilon(1e-4));
  }
  for (size_t i = 0; i < mask.size(); ++i)
    if (!mask[i]) CHECK(out[i] == m.positions()[i]);
  // Close to the truth on a walk (bones turn smoothly), and far better than doing nothing.
  CHECK(WorstMissing(out, m.positions(), mask) < 0.2);
}

TEST_CASE("the refiner's fills: root-relative, the mask, frames to the nearest observed value") {
  const Motion m = testing::MakeWalkingMotion(20);
  const Skeleton& sk = m.skeleton();
  const int J = sk.num_joints(), N = 3 * (J - 1), leaf = J - 1;
  std::vector<uint8_t> mask(m.positions().size(), 0);
  Hide(&mask, J, leaf, 5, 8);    // a 4-frame gap
  Hide(&mask, J, leaf, 17, 19);  // to the end
  Hide(&mask, J, 1, 0, 19);      // never observed
  std::vector<float> fallback(static_cast<size_t>(J) * 3, 0.25f);
  const RefinerFills f = MakeRefinerFills(sk, m.positions(), mask, fallback);
  REQUIRE(f.frames == 20);
  REQUIRE(f.before.size() == static_cast<size_t>(20) * N);
  const int v = 3 * (leaf - 1);  // the leaf's x among the non-root coordinates
  auto at = [&](const auto& x, int t, int c) { return x[t * N + c]; };
  const std::vector<float> before = {0, 1, 2, 3, 4, 0}, after = {0, 4, 3, 2, 1, 0};
  for (int t = 4; t <= 9; ++t) {
    CHECK(at(f.before, t, v) == before[t - 4]);
    CHECK(at(f.after, t, v) == after[t - 4]);
    CHECK(at(f.mask, t, v + 2) == (t >= 5 && t <= 8));
  }
  CHECK(at(f.before, 19, v) == 3);
  CHECK(at(f.after, 17, v) == kRefinerGapCap);   // no observed value after: "none"
  CHECK(at(f.before, 10, 0) == kRefinerGapCap);  // joint 1 never observed
  CHECK(at(f.after, 0, 0) == kRefinerGapCap);
  // Observed values are the motion's, root-relative; never-observed ones the fallback's.
  const std::vector<float>& p = m.positions();
  CHECK(at(f.spline, 3, v) == Approx(p[(3 * J + leaf) * 3] - p[3 * J * 3]).margin(1e-6));
  CHECK(at(f.linear, 10, 0) == Approx(0.25f).margin(1e-6));  // the fallback, about the root
  // Two windows appended: the second after the first.
  RefinerFills all;
  AppendRefinerFills(f, &all);
  AppendRefinerFills(f, &all);
  CHECK(all.frames == 20);
  CHECK(all.after.size() == 2 * f.after.size());
  CHECK(all.rigid[f.rigid.size() + 7] == f.rigid[7]);
}

TEST_CASE("the refiner's calibration buckets: gap length x edge speed x a crowded frame") {
  // Gap length = before + after - 1 while both are bracketed; speed: slow, medium, fast.
  CHECK(RefinerGapBucket(1, 1, 0, false) == 0);                // a 1-frame gap, slow
  CHECK(RefinerGapBucket(1, 2, 0, true) == 7);                 // 2 frames, slow, crowded
  CHECK(RefinerGapBucket(2, 3, 0.005f, false) == 14);          // 4 frames: 3-4, medium
  CHECK(RefinerGapBucket(1, 5, 0.02f, false) == 22);           // 5: 5-8, fast
  CHECK(RefinerGapBucket(4, 6, 0, false) == 24);               // 9: 9-16
  CHECK(RefinerGapBucket(30, 31, 0, false) == 36);             // 60: 33+
  CHECK(RefinerGapBucket(3, kRefinerGapCap, 0, false) == 42);  // not bracketed
  CHECK(RefinerGapBucket(kRefinerGapCap, kRefinerGapCap, 0.1f, true) == 47);
  CHECK(RefinerGapBucketName(5) == "gap 1, fast, crowded");
  CHECK(RefinerGapBucketName(14) == "gap 3-4, medium, sparse");
  CHECK_THROWS_AS(RefinerGapBucketName(kRefinerGapBuckets), std::invalid_argument);

  // Edge speed: the step just outside the gap, or the mean step across it.
  RefinerFills g;
  g.frames = 6;
  g.coords = 1;
  g.spline = {0, 0.02f, 0.04f, 0.045f, 0.048f, 0.05f};
  g.mask = {0, 0, 0, 1, 1, 0};
  g.before = {0, 0, 0, 1, 2, 0};
  g.after = {0, 0, 0, 2, 1, 0};
  CHECK(RefinerEdgeSpeed(g, 3, 0) == Approx(0.02f));                        // frame 2 - frame 1
  CHECK(RefinerGapBuckets(g) == std::vector<int>{-1, -1, -1, 11, 11, -1});  // 2, fast, crowded

  const Motion m = testing::MakeWalkingMotion(20);
  const Skeleton& sk = m.skeleton();
  const int J = sk.num_joints(), N = 3 * (J - 1), leaf = J - 1;
  std::vector<uint8_t> mask(m.positions().size(), 0);
  Hide(&mask, J, leaf, 5, 8);                             // a 4-frame gap, few values missing
  for (int j = 1; j < J; ++j) Hide(&mask, J, j, 12, 12);  // frame 12: every value
  const RefinerFills f = MakeRefinerFills(sk, m.positions(), mask, {});
  REQUIRE(f.coords == N);
  const std::vector<int> buckets = RefinerGapBuckets(f);
  const int v = 3 * (leaf - 1);
  const int gap4 = buckets[6 * N + v], crowded1 = buckets[12 * N];
  CHECK(buckets[4 * N + v] == -1);                  // observed
  CHECK((gap4 / 6 == 2 && gap4 % 2 == 0));          // gap 3-4, sparse
  CHECK((crowded1 / 6 == 0 && crowded1 % 2 == 1));  // gap 1, crowded
  std::vector<double> weights(kRefinerGapBuckets, 0.0);
  weights[gap4] = 0.5;
  const std::vector<float> w = RefinerValueWeights(f, weights);
  CHECK(w[6 * N + v] == 0.5f);
  CHECK(w[12 * N] == 0.0f);
  CHECK(RefinerValueWeights(f, {})[12 * N] == 1.0f);  // uncalibrated: 1 where missing
  CHECK(RefinerValueWeights(f, {})[4 * N + v] == 0.0f);
  CHECK_THROWS_AS(RefinerValueWeights(f, {1.0, 2.0}), std::invalid_argument);
}

TEST_CASE(
    "the local polynomial fills short gaps of a smooth motion exactly, long ones as the spline") {
  // One joint besides the root, moving along a degree-5 polynomial in time (exact for degree <= 7).
  const int T = 40, J = 2;
  auto curve = [](int t) {
    const double u = (t - 20) / 20.0;
    return 0.3 * u + 0.2 * u * u - 0.4 * u * u * u + 0.1 * std::pow(u, 5);
  };
  std::vector<float> p;
  for (int t = 0; t < T; ++t)
    p.insert(p.end(), {0, 0, 0, float(curve(t)), float(0.5 * curve(t)), 0.1f});
  std::vector<uint8_t> mask(p.size(), 0);
  Hide(&mask, J, 1, 10, 12);  // 3 frames: the polynomial
  Hide(&mask, J, 1, 20, 29);  // 10 frames: the spline
  const std::vector<float> local = InterpolateMissing(p, mask, J, Interpolation::kLocalPolynomial);
  const std::vector<float> spline = InterpolateMissing(p, mask, J, Interpolation::kCubicSpline);
  for (int t = 10; t <= 12; ++t) {
    const size_t i = (t * J + 1) * 3;
    CHECK(local[i] == Approx(p[i]).margin(1e-6));
    CHECK(local[i + 1] == Approx(p[i + 1]).margin(1e-6));
    CHECK(std::abs(spline[i] - p[i]) > 1e-6);  // the spline only comes close
  }
  for (int t = 20; t <= 29; ++t) CHECK(local[(t * J + 1) * 3] == spline[(t * J + 1) * 3]);
  for (size_t i = 0; i < p.size(); ++i)
    if (!mask[i]) CHECK(local[i] == p[i]);
  // A gap near the start: fewer frames on one side, still exact for a low degree.
  std::vector<uint8_t> early(p.size(), 0);
  Hide(&early, J, 1, 1, 2);
  const std::vector<float> e = InterpolateMissing(p, early, J, Interpolation::kLocalPolynomial);
  CHECK(e[(1 * J + 1) * 3] == Approx(p[(1 * J + 1) * 3]).margin(1e-5));
}
