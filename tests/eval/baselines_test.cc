// The zero-velocity and nearest-neighbour baselines on constructed motions.
#include "eval/baselines.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "core/limbs.h"
#include "eval/metrics.h"
#include "test_support.h"

using namespace motionfork;

namespace {

constexpr int kHis = 3, kPred = 4;  // windows of 7 frames

// The humanoid standing still, every non-root joint shifted by `shift` metres along X.
Motion Still(int frames, float shift, float root_x = 0.0f) {
  const Motion walk = testing::MakeWalkingMotion(1);
  std::vector<float> p;
  for (int t = 0; t < frames; ++t) {
    for (int j = 0; j < 17; ++j) {
      for (int a = 0; a < 3; ++a) {
        p.push_back(walk.at(0, j)[a] - walk.at(0, 0)[a] +
                    (a == 0 ? root_x + (j > 0 ? shift : 0.0f) : 0.0f));
      }
    }
  }
  return Motion(walk.skeleton_ptr(), 30, std::move(p));
}

std::vector<float> History(const Motion& m, int start) {
  return std::vector<float>(m.frame(start), m.frame(start + kHis));
}

double Norm3(const float* a, const float* b) {
  const double v[3] = {double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]};
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace

TEST_CASE("zero-velocity repeats the last observed pose in every sample and frame") {
  const Motion m = testing::MakeWalkingMotion(10);
  ZeroVelocityPredictor zv(m.skeleton_ptr(), kHis, kPred);
  std::vector<float> futures;
  PredictRequest r;
  r.num_samples = 3;
  zv.Predict(History(m, 2), r, &futures);
  REQUIRE(futures.size() == 3u * kPred * 17 * 3);
  for (size_t i = 0; i < futures.size(); ++i) CHECK(futures[i] == m.frame(4)[i % 51]);
  CHECK_THROWS_WITH(zv.Predict(std::vector<float>(10), r, &futures),
                    Catch::Contains("expected a history of [3, 17, 3] = 153 values, got 10"));
  r.num_samples = 0;
  CHECK_THROWS_WITH(zv.Predict(History(m, 0), r, &futures), Catch::Contains("num_samples >= 1"));
  r.num_samples = 2;
  r.fixed_part = 2;  // the humanoid's default partition has 2 parts
  CHECK_THROWS_WITH(zv.Predict(History(m, 0), r, &futures), Catch::Contains("got 2"));
}

TEST_CASE("nearest neighbours: training windows with stride 5 and the include-last rule") {
  // Clips of 7, 12, 16 and 6 frames; window 7 frames, stride 5.
  const Motion a = Still(7, 0), b = Still(12, 0), c = Still(16, 0), d = Still(6, 0);
  for (bool include_last : {true, false}) {
    NearestNeighbourOptions o;
    o.include_last = include_last;
    NearestNeighbourPredictor nn({&a, &b, &c, &d}, kHis, kPred, o);
    int expected = 0;
    for (int frames : {7, 12, 16, 6}) {
      for (int s = 0; include_last ? s <= frames - 7 : s < frames - 7; s += 5) ++expected;
    }
    // include_last: 1 + 2 (0, 5) + 2 (0, 5; 10 > 9) = 5; excluded: 0 + 1 + 2 = 3.
    CHECK(expected == (include_last ? 5 : 3));
    CHECK(nn.num_training_windows() == expected);
  }
  NearestNeighbourPredictor nn({&c}, kHis, kPred);
  CHECK(nn.training_window(1).start == 5);
  CHECK_THROWS_WITH(NearestNeighbourPredictor({&d}, kHis, kPred), Catch::Contains("7 frames"));
  CHECK_THROWS_WITH(NearestNeighbourPredictor({}, kHis, kPred),
                    Catch::Contains("0 training clips"));
}

TEST_CASE("nearest neighbours: nearest first by last-pose distance, ties by window index") {
  // Still clips of 12 frames (2 windows each) whose last history poses are 4 x |shift| away from
  // the rest pose (16 joints shifted along X). Clip 0: 1.2 m, clip 1: 0.4 m, clip 2: 0.8 m,
  // clip 3: a copy of clip 1 (0.4 m, an exact tie).
  const Motion c0 = Still(12, 0.3f), c1 = Still(12, 0.1f), c2 = Still(12, 0.2f), c3 = c1;
  NearestNeighbourPredictor nn({&c0, &c1, &c2, &c3}, kHis, kPred);
  REQUIRE(nn.num_training_windows() == 8);
  const Motion query = Still(kHis, 0);
  CHECK(nn.Neighbours(query.frame(0), 8) == std::vector<int>{2, 3, 6, 7, 4, 5, 0, 1});
  CHECK(nn.Neighbours(query.frame(0), 3) == std::vector<int>{2, 3, 6});
  CHECK_THROWS_WITH(nn.Neighbours(query.frame(0), 9), Catch::Contains("[1, 8]"));
  // Root-relative: the same poses standing 3 m away are as near (up to float rounding).
  const Motion c1_away = Still(12, 0.1f, 3.0f);
  NearestNeighbourPredictor away({&c0, &c1_away, &c2}, kHis, kPred);
  const std::vector<int> near = away.Neighbours(query.frame(0), 6);
  CHECK(std::vector<int>(near.begin(), near.begin() + 2) == std::vector<int>{2, 3});
  std::vector<float> futures;
  PredictRequest r;
  r.num_samples = 9;
  CHECK_THROWS_WITH(nn.Predict(History(query, 0), r, &futures), Catch::Contains("got 9"));
}

TEST_CASE(
    "nearest neighbours: futures keep the neighbour's limb directions, take the history's "
    "bone lengths, and move the root as the neighbour's did") {
  const Motion train = testing::MakeWalkingMotion(40, 30, 11);
  // A bigger body elsewhere: scale a different walk by 1.25 about the origin.
  const Motion walk = testing::MakeWalkingMotion(20, 30, 3);
  std::vector<float> big = walk.positions();
  for (float& v : big) v *= 1.25f;
  const Motion person(walk.skeleton_ptr(), 30, big);
  NearestNeighbourPredictor nn({&train}, kHis, kPred);
  const std::vector<float> history = History(person, 10);
  PredictRequest r;
  r.num_samples = 4;
  std::vector<float> futures;
  nn.Predict(history, r, &futures);
  const std::vector<int> near = nn.Neighbours(history.data(), 4);
  const float* last = history.data() + (kHis - 1) * 51;
  const auto& s = *walk.skeleton_ptr();
  for (int k = 0; k < 4; ++k) {
    const Window& w = nn.training_window(near[k]);
    const Limbs ref = ToLimbs(train.Slice(w.start + kHis, w.start + kHis + kPred));
    for (int t = 0; t < kPred; ++t) {
      const float* f = futures.data() + (static_cast<size_t>(k) * kPred + t) * 51;
      for (int j = 1; j < 17; ++j) {
        const double len = Norm3(f + 3 * j, f + 3 * s.parent(j));
        CHECK(len == Approx(Norm3(last + 3 * j, last + 3 * s.parent(j))).margin(1e-5));
        for (int a = 0; a < 3; ++a) {
          const double dir = (double(f[3 * j + a]) - f[3 * s.parent(j) + a]) / len;
          CHECK(dir ==
                Approx(ref.directions[(static_cast<size_t>(t) * 16 + j - 1) * 3 + a]).margin(1e-5));
        }
      }
      for (int a = 0; a < 3; ++a) {
        const float moved = train.at(w.start + kHis + t, 0)[a] - train.at(w.start + kHis - 1, 0)[a];
        CHECK(f[a] == Approx(last[a] + moved).margin(1e-5));
      }
    }
  }
  // The nearest neighbour of a training history is its own window (start 10 = window 2).
  CHECK(nn.Neighbours(History(train, 10).data(), 1)[0] == 2);
}

TEST_CASE("nearest neighbours with a fixed part: the part's limbs come from the nearest window") {
  const Motion train = testing::MakeWalkingMotion(120, 30, 11);
  const Motion person = testing::MakeWalkingMotion(20, 30, 3);
  NearestNeighbourPredictor nn({&train}, kHis, kPred);
  const auto& partition = person.skeleton().GetPartition();
  REQUIRE(partition.parts[0].name == "legs");
  PredictRequest r;
  r.num_samples = 6;
  r.fixed_part = 0;
  std::vector<float> futures;
  nn.Predict(History(person, 5), r, &futures);
  // Root-relative pose vectors [K, T, 48]: the legs' components agree across samples.
  std::vector<float> samples;
  for (size_t f = 0; f < futures.size() / 51; ++f) {
    for (int e = 3; e < 51; ++e) samples.push_back(futures[f * 51 + e] - futures[f * 51 + e % 3]);
  }
  std::vector<int> legs, upper;
  for (int j : partition.parts[0].joints) {
    for (int a = 0; a < 3; ++a) legs.push_back(3 * (j - 1) + a);
  }
  for (int j : partition.parts[1].joints) {
    for (int a = 0; a < 3; ++a) upper.push_back(3 * (j - 1) + a);
  }
  // Zero up to float rounding of world positions (each sample's root moves differently).
  CHECK(ApdOfDims(samples.data(), 6, kPred, 48, legs) == Approx(0.0).margin(1e-5));
  CHECK(ApdOfDims(samples.data(), 6, kPred, 48, upper) > 0.01);
}
