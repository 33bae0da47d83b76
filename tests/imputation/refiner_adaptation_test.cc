// Adapting the refiner's calibrated blend to one motion (no LibTorch): the least-squares weights
// with a prior, the probe masks and the adaptation with stand-in refiners whose worth is known.
#include "imputation/refiner_adaptation.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "imputation/blend_fit.h"
#include "imputation/bone_lengths.h"
#include "imputation/gap_imputation.h"
#include "test_support.h"

using namespace motionfork;

namespace {

// Sums of n values whose spline error is e, refiner correction c and local correction l each.
BlendSums Repeated(int n, double e, double c, double l) {
  BlendSums s;
  for (int i = 0; i < n; ++i) s.Add(e, c, l);
  return s;
}

ImputationBlend WithPrior(ImputationBlend b, double values) {
  b.adapt_values = {values};
  return b;
}

// Root-relative coordinates without the root of positions [T, J, 3].
std::vector<float> RootRelative(const std::vector<float>& p, int J) {
  const size_t F = static_cast<size_t>(J) * 3, T = p.size() / F, N = F - 3;
  std::vector<float> out(T * N);
  for (size_t t = 0; t < T; ++t)
    for (size_t v = 0; v < N; ++v) out[t * N + v] = p[t * F + 3 + v] - p[t * F + v % 3];
  return out;
}

}  // namespace

TEST_CASE("blend weights: least squares in [0, 1], pulled towards a prior by its worth") {
  // The refiner's correction is exactly the error: a = 1, the local one adds nothing.
  const BlendSums exact = Repeated(100, 0.02, 0.02, 0.0);
  auto [a, b] = BestBlendWeights(exact);
  CHECK(a == Approx(1));
  CHECK(b == Approx(0));
  CHECK(BlendSquares(exact, a, b) == Approx(0).margin(1e-12));
  // Half the correction is right: a = 0.5; a correction twice the error would want 0.5 too.
  CHECK(BestBlendWeights(Repeated(10, 0.01, 0.02, 0.0)).first == Approx(0.5));
  // The wrong way round: clamped to 0.
  CHECK(BestBlendWeights(Repeated(10, 0.01, -0.02, 0.0)).first == Approx(0));
  // A prior worth no values leaves the fit; a huge one keeps the prior; equal worth lands between.
  CHECK(BestBlendWeights(exact, 0.0, 0.0, 0.0).first == Approx(1));
  BlendSums both = Repeated(50, 0.02, 0.02, 0.01);
  both += Repeated(50, 0.01, 0.01, -0.01);
  CHECK(BestBlendWeights(both).first == Approx(1));
  CHECK(BestBlendWeights(both).second == Approx(0).margin(1e-9));
  CHECK(BestBlendWeights(both, 0.2, 0.3, 1e12).first == Approx(0.2).margin(1e-6));
  CHECK(BestBlendWeights(both, 0.2, 0.3, 1e12).second == Approx(0.3).margin(1e-6));
  const double between = BestBlendWeights(exact, 0.0, 0.0, 100).first;
  CHECK(between > 0.1);
  CHECK(between < 0.9);
  // Nothing known, or no correction to weigh: the prior as it is.
  CHECK(BestBlendWeights(BlendSums{}, 0.7, 0.1, 10) == std::pair<double, double>{0.7, 0.1});
  CHECK(BestBlendWeights(Repeated(5, 0.01, 0.0, 0.0), 0.7, 0.1, 10) ==
        std::pair<double, double>{0.7, 0.1});
}

TEST_CASE("probe masks hide observed values in the pattern of the missing ones") {
  const Motion motion = testing::MakeWalkingMotion(40, 30, 3);
  const Skeleton& sk = motion.skeleton();
  const int J = sk.num_joints(), N = 3 * (J - 1), T = 40;
  std::vector<uint8_t> missing(static_cast<size_t>(T) * J * 3, 0);
  // Joint 5 missing in frames 10..12 (a 3-frame gap); joint 7 missing throughout (not counted).
  for (int t = 0; t < T; ++t) {
    for (int a = 0; a < 3; ++a) {
      if (t >= 10 && t <= 12) missing[(static_cast<size_t>(t) * J + 5) * 3 + a] = 1;
      missing[(static_cast<size_t>(t) * J + 7) * 3 + a] = 1;
    }
  }
  const std::vector<float> fallback(static_cast<size_t>(J) * 3, 0.0f);
  const RefinerFills f = MakeRefinerFills(sk, motion.positions(), missing, fallback);
  const std::vector<std::vector<uint8_t>> probes = RefinerProbes(f);
  REQUIRE(probes.size() == 4);  // shifts +4, -4, +8, -8
  // Each probe hides fewer than kProbeValues values, so copies 20 frames (5 d) further are added
  // where they land whole, 4 frames clear of the gap, the hidden values and the motion's ends:
  // -4 + 20 and -8 + 20 do; +4 + 20 and +8 + 20 would end within 4 frames of the end.
  const std::vector<std::vector<int>> firsts = {{14}, {6, 26}, {18}, {2, 22}};
  for (size_t p = 0; p < probes.size(); ++p) {
    INFO("probe " << p);
    int hidden = 0;
    for (int t = 0; t < T; ++t) {
      for (int v = 0; v < N; ++v) {
        const size_t i = static_cast<size_t>(t) * N + v;
        if (!probes[p][i]) continue;
        ++hidden;
        CHECK_FALSE(f.mask[i]);  // only observed values are hidden
        CHECK(v / 3 + 1 == 5);   // of the joint with the gap
        CHECK(std::any_of(firsts[p].begin(), firsts[p].end(), [t](int first) {
          return t >= first && t < first + 3;  // as long as the gap, shifted
        }));
      }
    }
    CHECK(hidden == 9 * static_cast<int>(firsts[p].size()));
  }
  // Nothing missing, or only whole coordinates: no probes.
  std::vector<uint8_t> whole(missing.size(), 0);
  for (int t = 0; t < T; ++t)
    for (int a = 0; a < 3; ++a) whole[(static_cast<size_t>(t) * J + 7) * 3 + a] = 1;
  CHECK(RefinerProbes(MakeRefinerFills(sk, motion.positions(), whole, fallback)).empty());
}

TEST_CASE("probe masks of a sparse mask add copies of its gaps, each clear of the others") {
  const int T = 3000;
  const Motion motion = testing::MakeWalkingMotion(T, 30, 5);
  const Skeleton& sk = motion.skeleton();
  const int J = sk.num_joints(), N = 3 * (J - 1);
  const std::vector<float> fallback(static_cast<size_t>(J) * 3, 0.0f);
  // One 8-frame gap of a joint: 24 values; d = 9, copies 45 frames apart.
  const std::vector<uint8_t> gap = GapMask({"hand gap", 0, {5}, 8}, T, J, /*seed=*/2);
  const RefinerFills f = MakeRefinerFills(sk, motion.positions(), gap, fallback);
  const std::vector<std::vector<uint8_t>> probes = RefinerProbes(f);
  REQUIRE(probes.size() == 4);
  const int d = 9;
  auto near = [&](const std::vector<uint8_t>& m, int t, int v) {  // anything within d frames
    for (int u = std::max(0, t - d); u <= std::min(T - 1, t + d); ++u)
      if (m[static_cast<size_t>(u) * N + v]) return true;
    return false;
  };
  for (const std::vector<uint8_t>& hide : probes) {
    int hidden = 0, runs = 0, off_pattern = 0;
    for (int t = 0; t < T; ++t) {
      for (int v = 0; v < N; ++v) {
        const size_t i = static_cast<size_t>(t) * N + v;
        if (!hide[i]) continue;
        ++hidden;
        CHECK_FALSE(f.mask[i]);
        CHECK(v / 3 + 1 == 5);
        if (t == 0 || !hide[i - N]) {
          ++runs;
          int length = 0;
          while (t + length < T && hide[static_cast<size_t>(t + length) * N + v]) ++length;
          CHECK(length == 8);  // every copy as long as the gap
          // Copies beyond the first are d frames clear of the real gap.
          if (!near(f.mask, t, v) && !near(f.mask, t + 7, v)) ++off_pattern;
        }
      }
    }
    CHECK(off_pattern >= 3 * (runs / 3 - 1));
    CHECK(hidden == runs * 8);
    CHECK(hidden >= kProbeValues);  // copies until kProbeValues are hidden (two at a time)
    CHECK(hidden < kProbeValues + 48);
  }
  // A dense mask (random 30%) hides more than kProbeValues with the four shifts alone: no copies,
  // so every hidden value is its shift's image of a missing one.
  const std::vector<uint8_t> dense = GapMask({"random 30%", 0.3, {}, 0}, T, J, /*seed=*/3);
  const RefinerFills g = MakeRefinerFills(sk, motion.positions(), dense, fallback);
  const std::vector<std::vector<uint8_t>> dense_probes = RefinerProbes(g);
  REQUIRE_FALSE(dense_probes.empty());
  int longest = 0;
  for (int v = 0; v < N; ++v)
    for (int t = 0, run = 0; t < T; ++t) {
      run = g.mask[static_cast<size_t>(t) * N + v] ? run + 1 : 0;
      longest = std::max(longest, run);
    }
  const int shifts[] = {longest + 1, -(longest + 1), 2 * (longest + 1), -2 * (longest + 1)};
  for (size_t p = 0; p < dense_probes.size(); ++p)
    for (int t = 0; t < T; ++t)
      for (int v = 0; v < N; ++v)
        if (dense_probes[p][static_cast<size_t>(t) * N + v]) {
          const int u = t - shifts[p];
          REQUIRE((u >= 0 && u < T));
          CHECK(g.mask[static_cast<size_t>(u) * N + v]);
        }
}

TEST_CASE("adapting the blend to a motion follows what its probes say about the refiner") {
  const Motion motion = testing::MakeWalkingMotion(60, 30, 11);
  const Skeleton& sk = motion.skeleton();
  const int J = sk.num_joints();
  const std::vector<float> truth = RootRelative(motion.positions(), J);
  const std::vector<uint8_t> missing =
      GapMask({"left arm gap", 0, {11, 12, 13}, 6}, 60, J, /*seed=*/4);
  const RefinerFills f = MakeRefinerFills(sk, motion.positions(), missing, {});
  // A refiner that knows the truth (probe fills hold the same motion) and one that adds noise.
  const RawRefiner oracle = [&](const RefinerFills&) { return truth; };
  const RawRefiner off = [&](const RefinerFills& p) {
    std::vector<float> out = p.spline;
    for (size_t i = 0; i < out.size(); ++i)
      if (p.mask[i]) out[i] += (i % 2 ? 0.05f : -0.05f);
    return out;
  };
  ImputationBlend calibrated;
  calibrated.refiner.assign(kRefinerGapBuckets, 0.5);
  calibrated.local.assign(kRefinerGapBuckets, 0.0);
  const ImputationBlend trusting =
      AdaptBlend(WithPrior(calibrated, 0.01), ProbeBlendSums(FillRefinerProbes(sk, f, oracle), f));
  const ImputationBlend doubting =
      AdaptBlend(WithPrior(calibrated, 0.01), ProbeBlendSums(FillRefinerProbes(sk, f, off), f));
  const ImputationBlend kept =
      AdaptBlend(WithPrior(calibrated, 1e12), ProbeBlendSums(FillRefinerProbes(sk, f, off), f));
  int reached = 0;
  for (int k = 0; k < kRefinerGapBuckets; ++k) {
    if (trusting.refiner[k] == 0.5 && doubting.refiner[k] == 0.5) continue;  // no probe here
    ++reached;
    CHECK(trusting.refiner[k] > 0.9);
    CHECK(doubting.refiner[k] < 0.1);
    CHECK(kept.refiner[k] == Approx(0.5).margin(1e-6));
  }
  CHECK(reached > 0);
  // A prior per gap length: the 6-frame gap's class (5-8 frames) held by a huge one, the others
  // free: that class keeps the calibrated weight, the others move as before.
  ImputationBlend per_length = calibrated;
  per_length.adapt_values.assign(kRefinerGapLengths, 0.01);
  per_length.adapt_values[3] = 1e12;
  const ImputationBlend held =
      AdaptBlend(per_length, ProbeBlendSums(FillRefinerProbes(sk, f, oracle), f));
  int held_buckets = 0;
  for (int k = 0; k < kRefinerGapBuckets; ++k) {
    if (trusting.refiner[k] == 0.5) continue;
    if (k / 6 == 3) {
      ++held_buckets;
      CHECK(held.refiner[k] == Approx(0.5).margin(1e-6));
    } else {
      CHECK(held.refiner[k] == trusting.refiner[k]);
    }
  }
  CHECK(held_buckets > 0);
  per_length.adapt_values[3] = 0.01;
  CHECK(AdaptBlend(per_length, ProbeBlendSums(FillRefinerProbes(sk, f, oracle), f)).refiner ==
        trusting.refiner);
  per_length.adapt_values.resize(3);
  CHECK_THROWS_AS(AdaptValues(per_length, 0), std::invalid_argument);
  // Blended with the adapted weights, the oracle's fill beats the calibrated blend's.
  auto error = [&](const ImputationBlend& b) {
    const std::vector<float> out = BlendRefinerFills(sk, f, oracle(f), b);
    double sum = 0;
    for (size_t i = 0; i < out.size(); ++i)
      if (f.mask[i]) sum += std::pow(double(out[i]) - truth[i], 2);
    return sum;
  };
  CHECK(error(trusting) < error(calibrated));
  CHECK_THROWS_AS(AdaptBlend(WithPrior(calibrated, 1), BucketSums(3)), std::invalid_argument);
}

TEST_CASE("adapting the bones' share: none where the fill is already closer than their spread") {
  // root -> elbow -> hand circling the elbow at 0.3 m, each hand coordinate off by up to 0.15 mm
  // (rigid by kRigidSpread), and a refiner that knows the motion: the bones' correction only
  // moves the fill off the truth.
  const Skeleton sk = Skeleton::FromParents("arm", {"root", "elbow", "hand"}, {-1, 0, 1});
  const int T = 60, J = 3;
  std::vector<float> p;
  for (int t = 0; t < T; ++t) {
    const double a = 0.2 * t, jitter = 0.00015 * ((t * 7 % 5) / 2.0 - 1.0);
    p.insert(p.end(), {0, 0, 0, 0, 1, 0, float(0.3 * std::cos(a) + jitter),
                       float(1 + 0.3 * std::sin(a) - jitter), float(jitter)});
  }
  const std::vector<float> truth = RootRelative(p, J);
  std::vector<uint8_t> missing(p.size(), 0);
  for (int t = 20; t < 25; ++t)
    for (int a = 0; a < 3; ++a) missing[(static_cast<size_t>(t) * J + 2) * 3 + a] = 1;
  REQUIRE(ObservedBones(sk, p, missing)[2].rigid());
  const RefinerFills f = MakeRefinerFills(sk, p, missing, std::vector<float>(J * 3, 0.0f));
  const std::vector<RefinerProbe> probes =
      FillRefinerProbes(sk, f, [&](const RefinerFills&) { return truth; });
  REQUIRE(probes.size() == 4);
  ImputationBlend blend;
  blend.refiner.assign(kRefinerGapBuckets, 1.0);
  blend.local.assign(kRefinerGapBuckets, 0.0);
  blend.keep_bones = true;
  const ImputationBlend adapted = AdaptBones(sk, WithPrior(blend, 0.01), probes, f);
  const ImputationBlend pulled = AdaptBones(sk, WithPrior(blend, 1e12), probes, f);
  REQUIRE(adapted.bones.size() == static_cast<size_t>(kRefinerGapBuckets));
  int reached = 0;
  for (int k = 0; k < kRefinerGapBuckets; ++k) {
    CHECK(pulled.bones[k] == Approx(1).margin(1e-6));
    if (adapted.bones[k] == 1.0) continue;  // no probe here
    ++reached;
    CHECK(adapted.bones[k] < 0.1);
  }
  CHECK(reached > 0);
  // A straight line cuts the circle's chord: there the bones' correction is wanted.
  const ImputationBlend chord =
      AdaptBones(sk, WithPrior(blend, 0.01),
                 FillRefinerProbes(sk, f, [](const RefinerFills& x) { return x.linear; }), f);
  CHECK(*std::max_element(chord.bones.begin(), chord.bones.end()) > 0.5);
  // ... and the real gap comes out closer with the adapted share than without the bones.
  auto error = [&](const ImputationBlend& b) {
    const std::vector<float> out = BlendRefinerFills(sk, f, f.linear, b);
    double sum = 0;
    for (size_t i = 0; i < out.size(); ++i)
      if (f.mask[i]) sum += std::pow(double(out[i]) - truth[i], 2);
    return sum;
  };
  ImputationBlend loose = chord;
  loose.keep_bones = false;
  CHECK(error(chord) < error(loose));
  // Without keep_bones nothing is fitted.
  blend.keep_bones = false;
  CHECK(AdaptBones(sk, WithPrior(blend, 0.01), probes, f).bones.empty());
}
