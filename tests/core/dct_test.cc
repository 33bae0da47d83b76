#include "core/dct.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace motionfork;

TEST_CASE("the DCT matrix is orthonormal and matches the seed formula") {
  for (int n : {1, 2, 15, 75, 125}) {
    const Eigen::MatrixXd d = DctMatrix(n);
    CHECK((d * d.transpose() - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff() < 1e-12);
  }
  // Eq. 6 with 1-based l, n, written out independently.
  const int N = 10;
  const Eigen::MatrixXd d = DctMatrix(N);
  for (int l = 1; l <= N; ++l) {
    for (int n = 1; n <= N; ++n) {
      const double delta = l == 1 ? 1.0 : 0.0;
      const double want = std::sqrt(2.0 / N) / std::sqrt(1 + delta) *
                          std::cos(M_PI / (2.0 * N) * (2 * n - 1) * (l - 1));
      CHECK(d(l - 1, n - 1) == Approx(want).margin(1e-14));
    }
  }
}

TEST_CASE("DCT then inverse DCT returns the trajectory to 1e-5") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-2, 2);
  Eigen::MatrixXf x(75, 48);
  for (int i = 0; i < x.size(); ++i) x.data()[i] = u(rng);
  const Eigen::MatrixXf back = InverseDct(Dct(x, 75), 75);
  CHECK((back - x).cwiseAbs().maxCoeff() < 1e-5f);
}

TEST_CASE("truncated DCT keeps smooth trajectories and drops high frequencies") {
  Eigen::MatrixXf x(75, 3);
  for (int t = 0; t < 75; ++t) {
    x(t, 0) = 0.3f;                                       // constant: one coefficient
    x(t, 1) = std::cos(M_PI / 150.0 * (2 * t + 1) * 4);   // exactly basis 4
    x(t, 2) = std::cos(M_PI / 150.0 * (2 * t + 1) * 40);  // basis 40: removed by truncation
  }
  const Eigen::MatrixXf c = Dct(x, 10);
  REQUIRE(c.rows() == 10);
  const Eigen::MatrixXf y = InverseDct(c, 75);
  CHECK((y.col(0) - x.col(0)).cwiseAbs().maxCoeff() < 1e-5f);
  CHECK((y.col(1) - x.col(1)).cwiseAbs().maxCoeff() < 1e-5f);
  CHECK(y.col(2).cwiseAbs().maxCoeff() < 1e-5f);
  CHECK_THROWS(Dct(x, 0));
  CHECK_THROWS(Dct(x, 76));
  CHECK_THROWS(InverseDct(c, 5));
}
