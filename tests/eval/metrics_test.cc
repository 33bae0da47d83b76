// The protocol metrics on hand-made cases whose answers are computed here independently.
#include "eval/metrics.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

using namespace motionfork;

namespace {

// K samples [K, T, D] filled by f(k, t, d).
template <typename F>
std::vector<float> Samples(int K, int T, int D, F f) {
  std::vector<float> s(static_cast<size_t>(K) * T * D);
  for (int k = 0; k < K; ++k)
    for (int t = 0; t < T; ++t)
      for (int d = 0; d < D; ++d) s[(static_cast<size_t>(k) * T + t) * D + d] = f(k, t, d);
  return s;
}

}  // namespace

TEST_CASE("identical samples have APD 0, exactly") {
  const int K = 50, T = 60, D = 48;
  const auto s = Samples(K, T, D, [](int, int t, int d) { return 0.3f * std::sin(0.1f * t + d); });
  CHECK(Apd(s.data(), K, T, D) == 0.0);
  CHECK(ApdOfDims(s.data(), K, T, D, {0, 1, 2, 47}) == 0.0);
}

TEST_CASE("APD of samples offset by known constants") {
  // Sample k = base + c_k in every component: ||x_i - x_j|| = |c_i - c_j| sqrt(T D).
  const int T = 4, D = 6;
  const float c[3] = {0.0f, 0.5f, 2.0f};
  const auto s = Samples(3, T, D, [&](int k, int t, int d) { return 0.1f * (t - d) + c[k]; });
  const double root = std::sqrt(double(T * D));
  // Ordered pairs: 2 x (0.5 + 2.0 + 1.5) / 6.
  const double expected = (0.5 + 2.0 + 1.5) * root / 3.0;
  CHECK(Apd(s.data(), 3, T, D) == Approx(expected).epsilon(1e-6));
  // Over 2 of the 6 components: the same offsets, sqrt(T * 2).
  CHECK(ApdOfDims(s.data(), 3, T, D, {1, 4}) ==
        Approx((0.5 + 2.0 + 1.5) * std::sqrt(double(T * 2)) / 3.0).epsilon(1e-6));
}

TEST_CASE("APD needs at least two samples") {
  const auto s = Samples(1, 3, 3, [](int, int, int) { return 0.0f; });
  CHECK_THROWS_WITH(Apd(s.data(), 1, 3, 3),
                    Catch::Contains("expected K >= 2") && Catch::Contains("got 1"));
  CHECK_THROWS_WITH(ApdOfDims(s.data(), 1, 3, 3, {0}), Catch::Contains("expected K >= 2"));
  CHECK_THROWS_WITH(ApdOfDims(s.data(), 2, 1, 3, {3}), Catch::Contains("[0, 3)"));
}

TEST_CASE("a known offset gives a known ADE and FDE") {
  const int T = 10, D = 48;
  const auto truth = Samples(1, T, D, [](int, int t, int d) { return 0.02f * t - 0.01f * d; });
  // One sample = truth + a constant offset of norm 0.3 m (on 4 components: 0.15 each).
  const auto one = Samples(1, T, D, [&](int, int t, int d) {
    return truth[static_cast<size_t>(t) * D + d] + (d < 4 ? 0.15f : 0.0f);
  });
  Displacement m = MinDisplacement(one.data(), 1, T, D, truth.data());
  CHECK(m.ade == Approx(0.3).epsilon(1e-6));
  CHECK(m.fde == Approx(0.3).epsilon(1e-6));

  // Sample 0 drifts linearly: offset (t + 1) / T * 0.4 m (ADE 0.4 (T + 1) / 2T = 0.22, FDE 0.4).
  // Sample 1 is off by 0.3 m in the first half and exact in the second (ADE 0.15, FDE 0).
  // Sample 2 is constantly 0.25 off (ADE 0.25, FDE 0.25). The minima pick different samples.
  const auto three = Samples(3, T, D, [&](int k, int t, int d) {
    const float g = truth[static_cast<size_t>(t) * D + d];
    if (d != 7) return g;
    if (k == 0) return g + 0.4f * (t + 1) / T;
    if (k == 1) return g - (t < T / 2 ? 0.3f : 0.0f);
    return g + 0.25f;
  });
  m = MinDisplacement(three.data(), 3, T, D, truth.data());
  CHECK(m.ade == Approx(0.15).epsilon(1e-6));
  CHECK(m.fde == Approx(0.0).margin(1e-7));
  // Without sample 1: ADE from sample 0 (0.22), FDE from sample 2 (0.25).
  const std::vector<float> two_of(three.begin(), three.begin() + T * D);
  std::vector<float> s02 = two_of;
  s02.insert(s02.end(), three.begin() + 2 * T * D, three.end());
  m = MinDisplacement(s02.data(), 2, T, D, truth.data());
  CHECK(m.ade == Approx(0.4 * (T + 1) / (2.0 * T)).epsilon(1e-6));
  CHECK(m.fde == Approx(0.25).epsilon(1e-6));

  // The distance is the L2 norm of the whole pose vector, not a mean per joint: an offset of
  // (0.3, 0.4, 0) on one joint and nothing elsewhere is 0.5 m.
  const auto joint = Samples(1, T, D, [&](int, int t, int d) {
    return truth[static_cast<size_t>(t) * D + d] + (d == 9 ? 0.3f : d == 10 ? 0.4f : 0.0f);
  });
  CHECK(MinDisplacement(joint.data(), 1, T, D, truth.data()).ade == Approx(0.5).epsilon(1e-6));
}

TEST_CASE("the matrix-product workspace agrees with the direct minima") {
  std::mt19937 rng(5);
  std::normal_distribution<float> n(0.0f, 0.4f);
  const int K = 20, T = 15, D = 48, M = 37;
  std::vector<float> samples(static_cast<size_t>(K) * T * D);
  for (float& v : samples) v = 1.0f + n(rng);  // offset from 0: poses are not centred
  std::vector<std::vector<float>> truth_data(M, std::vector<float>(static_cast<size_t>(T) * D));
  for (auto& t : truth_data)
    for (float& v : t) v = 1.0f + n(rng);
  // Truth 3 equals sample 4 (distance 0), truth 5 is within a millimetre of sample 0.
  std::copy(samples.begin() + 4 * T * D, samples.begin() + 5 * T * D, truth_data[3].begin());
  for (int e = 0; e < T * D; ++e) truth_data[5][e] = samples[e] + (e % 7 == 0 ? 1e-4f : 0.0f);
  std::vector<const float*> truths;
  for (const auto& t : truth_data) truths.push_back(t.data());
  DisplacementWorkspace ws;
  std::vector<Displacement> fast;
  for (int repeat = 0; repeat < 2; ++repeat) {  // a warm workspace gives the same answers
    ws.Run(samples.data(), K, T, D, truths, &fast);
    REQUIRE(fast.size() == static_cast<size_t>(M));
    for (int m = 0; m < M; ++m) {
      const Displacement ref = MinDisplacement(samples.data(), K, T, D, truths[m]);
      CHECK(fast[m].ade == Approx(ref.ade).margin(2e-6));
      CHECK(fast[m].fde == Approx(ref.fde).margin(2e-6));
    }
  }
  CHECK(fast[3].ade == 0.0);
  CHECK(fast[3].fde == 0.0);
  CHECK(fast[5].ade ==
        Approx(MinDisplacement(samples.data(), K, T, D, truths[5]).ade).margin(1e-7));
  ws.Run(samples.data(), K, T, D, {}, &fast);
  CHECK(fast.empty());
}
