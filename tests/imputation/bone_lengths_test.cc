// Keeping filled joints at their bones' observed lengths (no LibTorch), alone and as the last step
// of the imputation blend.
#include "imputation/bone_lengths.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "imputation/interpolation_fill.h"
#include "imputation/refiner_fills.h"

using namespace motionfork;
using Catch::Contains;

namespace {

// root -> elbow (fixed) -> hand circling the elbow at radius 0.3 m; a fourth joint on the root
// whose "bone" stretches by +-2 cm (a protocol skeleton skipping a joint).
constexpr int kJ = 4, kT = 40;
Skeleton Arm() {
  return Skeleton::FromParents("arm", {"root", "elbow", "hand", "loose"}, {-1, 0, 1, 0});
}

std::vector<float> ArmMotion() {
  std::vector<float> p;
  for (int t = 0; t < kT; ++t) {
    const double a = 0.25 * t, s = 0.5 + 0.02 * std::sin(0.7 * t);
    p.insert(p.end(), {0, 0, 0, 0, 1, 0, float(0.3 * std::cos(a)), float(1 + 0.3 * std::sin(a)), 0,
                       float(s), 0, 0});
  }
  return p;
}

void Hide(std::vector<uint8_t>* mask, int j, int first, int last) {
  for (int t = first; t <= last; ++t)
    for (int a = 0; a < 3; ++a) (*mask)[(static_cast<size_t>(t) * kJ + j) * 3 + a] = 1;
}

double Distance(const std::vector<float>& p, int t, int a, int b) {
  double s = 0;
  for (int k = 0; k < 3; ++k) s += std::pow(p[(t * kJ + a) * 3 + k] - p[(t * kJ + b) * 3 + k], 2);
  return std::sqrt(s);
}

}  // namespace

TEST_CASE("bones observed rigid are kept at their length; stretching ones are left alone") {
  const Skeleton sk = Arm();
  const std::vector<float> p = ArmMotion();
  std::vector<uint8_t> mask(p.size(), 0);
  Hide(&mask, 2, 10, 14);  // the hand for 5 frames: straight lines cut the circle's chord
  Hide(&mask, 3, 20, 22);  // the loose joint
  const std::vector<ObservedBone> bones = ObservedBones(sk, p, mask);
  CHECK(bones[2].length == Approx(0.3).epsilon(1e-5));
  CHECK(bones[2].rigid());
  CHECK(bones[2].frames == kT - 5);
  CHECK_FALSE(bones[3].rigid());  // strays 2 cm
  CHECK(bones[3].spread > kRigidSpread);

  const std::vector<float> linear = InterpolateMissing(p, mask, kJ, Interpolation::kLinear);
  const std::vector<float> kept = KeepBoneLengths(sk, linear, mask);
  for (int t = 10; t <= 14; ++t) {
    CHECK(Distance(linear, t, 2, 1) < 0.29);  // the chord
    CHECK(Distance(kept, t, 2, 1) == Approx(0.3).epsilon(1e-4));
  }
  double se_linear = 0, se_kept = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!mask[i]) {
      CHECK(kept[i] == linear[i]);  // observed values never move
      continue;
    }
    se_linear += std::pow(linear[i] - p[i], 2);
    se_kept += std::pow(kept[i] - p[i], 2);
  }
  CHECK(se_kept < 0.5 * se_linear);
  for (int t = 20; t <= 22; ++t)  // the stretching bone: unchanged
    for (int k = 0; k < 3; ++k) CHECK(kept[(t * kJ + 3) * 3 + k] == linear[(t * kJ + 3) * 3 + k]);
  CHECK_THROWS_WITH(KeepBoneLengths(sk, linear, std::vector<uint8_t>(5)),
                    Contains("KeepBoneLengths"));
}

TEST_CASE("a joint between two observed ones lands on both spheres") {
  const Skeleton sk = Arm();
  const std::vector<float> p = ArmMotion();
  std::vector<uint8_t> mask(p.size(), 0);
  Hide(&mask, 1, 5, 5);  // the elbow: fixed at (0, 1, 0); bones to the root (1 m) and hand (0.3 m)
  std::vector<float> off = p;
  off[(5 * kJ + 1) * 3] += 0.05f;  // a fill 5 cm off
  off[(5 * kJ + 1) * 3 + 1] -= 0.04f;
  const std::vector<float> kept = KeepBoneLengths(sk, off, mask, 50);
  CHECK(Distance(kept, 5, 1, 0) == Approx(1.0).epsilon(1e-3));
  CHECK(Distance(kept, 5, 2, 1) == Approx(0.3).epsilon(1e-3));
}

TEST_CASE("the imputation blend: spline, refiner and local polynomial by bucket, then bones") {
  const Skeleton sk = Arm();
  const std::vector<float> p = ArmMotion();
  std::vector<uint8_t> mask(p.size(), 0);
  Hide(&mask, 2, 10, 12);
  const RefinerFills f = MakeRefinerFills(sk, p, mask, {});
  std::vector<float> refined = f.spline;
  for (size_t i = 0; i < refined.size(); ++i)
    if (f.mask[i]) refined[i] += 0.01f;
  const std::vector<double> zeros(kRefinerGapBuckets, 0.0), ones(kRefinerGapBuckets, 1.0);
  const std::vector<float> spline =
      BlendRefinerFills(sk, f, refined, {zeros, zeros, false, {}, {}, {}, {}});
  const std::vector<float> local =
      BlendRefinerFills(sk, f, refined, {zeros, ones, false, {}, {}, {}, {}});
  const std::vector<float> both =
      BlendRefinerFills(sk, f, refined, {ones, ones, false, {}, {}, {}, {}});
  for (size_t i = 0; i < f.mask.size(); ++i) {
    CHECK(spline[i] == Approx(f.spline[i]).margin(1e-7));
    CHECK(local[i] == Approx(f.local[i]).margin(1e-7));
    if (f.mask[i]) CHECK(both[i] == Approx(f.local[i] + 0.01f).margin(1e-6));
  }
  const std::vector<float> bones =
      BlendRefinerFills(sk, f, refined, {ones, zeros, true, {}, {}, {}, {}});
  const int N = f.coords, hand = 3 * (2 - 1), elbow = 0;
  for (int t = 10; t <= 12; ++t) {
    double s = 0;
    for (int k = 0; k < 3; ++k)
      s += std::pow(bones[t * N + hand + k] - bones[t * N + elbow + k], 2);
    CHECK(std::sqrt(s) == Approx(0.3).epsilon(1e-4));
  }
  CHECK_THROWS_AS(BlendRefinerFills(sk, f, std::vector<float>(3), {}), std::invalid_argument);
}
