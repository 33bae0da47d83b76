#include "core/rotation_fit.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace motionfork {

void FitRotation(const std::vector<double>& u, const std::vector<double>& v,
                 const std::vector<double>& w, double* r) {
  using Eigen::Matrix3d;
  using Eigen::Vector3d;
  const size_t n = u.size() / 3;
  const auto at = [](const std::vector<double>& x, size_t i) {
    return Vector3d(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  };
  const auto shortest = [](const Vector3d& a, const Vector3d& b) {
    if (a.norm() < 1e-12 || b.norm() < 1e-12) return Matrix3d(Matrix3d::Identity());
    return Matrix3d(Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix());
  };
  Matrix3d m = Matrix3d::Identity();
  if (n == 1) {
    m = shortest(at(u, 0), at(v, 0));
  } else if (n > 1) {
    Matrix3d h = Matrix3d::Zero();
    Vector3d su = Vector3d::Zero(), sv = Vector3d::Zero();
    for (size_t i = 0; i < n; ++i) {
      const double wi = w.empty() ? 1.0 : w[i];
      h += wi * at(u, i) * at(v, i).transpose();
      su += wi * at(u, i);
      sv += wi * at(v, i);
    }
    const Eigen::JacobiSVD<Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    if (!(svd.singularValues()(0) > 0)) {
      m = Matrix3d::Identity();  // every direction zero: nothing to turn by
    } else if (svd.singularValues()(1) < 1e-9 * svd.singularValues()(0)) {
      m = shortest(su, sv);  // collinear: no turn about the line is told, take none
    } else {
      Matrix3d d = Matrix3d::Identity();
      if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) d(2, 2) = -1;
      m = svd.matrixV() * d * svd.matrixU().transpose();
    }
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[3 * i + j] = m(i, j);
}

}  // namespace motionfork
