// Motions built from joint rotations (so the exact rotations are known): the test humanoid's
// frame-0 pose as the rest, smooth random local rotations, forward kinematics with Eigen (no code
// shared with core/pose_fitting or the BVH reader).
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/limbs.h"
#include "core/motion.h"
#include "test_support.h"

namespace motionfork::testing {

struct RotatedMotion {
  Motion motion;                       // [T, 17, 3] metres, every bone of constant length
  std::vector<Eigen::Matrix3d> world;  // [T, J] joint frame -> world, rest pose = identity
};

// frames at 30 Hz; local rotations up to about max_angle_deg about random axes, the root also
// turning about +Y by yaw_deg_per_s (past 180 degrees in a few seconds, to test unwrapping).
inline RotatedMotion MakeRotatedMotion(int frames, unsigned seed = 3, double max_angle_deg = 60,
                                       double yaw_deg_per_s = 120) {
  const Motion rest = MakeWalkingMotion(1);
  const Skeleton& s = rest.skeleton();
  const int J = s.num_joints();
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0, 6.283);
  std::vector<Eigen::Vector3d> axis_a(J), axis_b(J);
  std::vector<double> phase(J);
  for (int j = 0; j < J; ++j) {
    axis_a[j] = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    axis_b[j] = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    phase[j] = uniform(rng);
  }
  const double max_angle = max_angle_deg * 3.14159265358979 / 180;
  RotatedMotion out;
  out.world.resize(static_cast<size_t>(frames) * J);
  std::vector<float> p(static_cast<size_t>(frames) * J * 3);
  for (int t = 0; t < frames; ++t) {
    const double time = t / 30.0;
    for (int j = 0; j < J; ++j) {
      Eigen::Matrix3d local =
          (Eigen::AngleAxisd(max_angle * std::sin(1.3 * time + phase[j]), axis_a[j]) *
           Eigen::AngleAxisd(0.5 * max_angle * std::sin(2.1 * time + 2 * phase[j]), axis_b[j]))
              .toRotationMatrix();
      const int par = s.parent(j);
      Eigen::Vector3d at;
      if (par < 0) {
        local = Eigen::AngleAxisd(yaw_deg_per_s * time * 3.14159265358979 / 180,
                                  Eigen::Vector3d::UnitY()) *
                local;
        at = Eigen::Vector3d(0.3 * time, 0.9 + 0.05 * std::sin(3 * time), 1.1 * time);
        out.world[t * J + j] = local;
      } else {
        const Eigen::Vector3d offset(rest.at(0, j)[0] - rest.at(0, par)[0],
                                     rest.at(0, j)[1] - rest.at(0, par)[1],
                                     rest.at(0, j)[2] - rest.at(0, par)[2]);
        const float* pp = &p[(static_cast<size_t>(t) * J + par) * 3];
        at = Eigen::Vector3d(pp[0], pp[1], pp[2]) + out.world[t * J + par] * offset;
        out.world[t * J + j] = out.world[t * J + par] * local;
      }
      for (int a = 0; a < 3; ++a)
        p[(static_cast<size_t>(t) * J + j) * 3 + a] = static_cast<float>(at[a]);
    }
  }
  out.motion = Motion(rest.skeleton_ptr(), 30.0, std::move(p));
  return out;
}

// Largest distance between the same joints of two motions of equal shape, metres.
// Infinity when the shapes differ.
inline double MaxDistance(const Motion& a, const Motion& b) {
  if (a.positions().size() != b.positions().size()) return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (int t = 0; t < a.num_frames(); ++t) {
    for (int j = 0; j < a.num_joints(); ++j) {
      const float* x = a.at(t, j);
      const float* y = b.at(t, j);
      const double d = std::sqrt((double(x[0]) - y[0]) * (double(x[0]) - y[0]) +
                                 (double(x[1]) - y[1]) * (double(x[1]) - y[1]) +
                                 (double(x[2]) - y[2]) * (double(x[2]) - y[2]));
      worst = std::max(worst, d);
    }
  }
  return worst;
}

// How far `out` is from `in` read as bone directions at the mean lengths (what a fit with
// BoneLengths::kMean keeps): the largest direction component error and the largest distance of
// a bone's length in `out` from that bone's mean length in `in`, metres.
struct MeanLengthDeviation {
  double direction = 0;
  double length = 0;
};
inline MeanLengthDeviation DeviationFromMeanLengths(const Motion& in, const Motion& out) {
  const Limbs a = ToLimbs(in), b = ToLimbs(out);
  const int T = a.num_frames, L = a.num_limbs;
  MeanLengthDeviation d;
  for (int k = 0; k < L; ++k) {
    double mean = 0;
    for (int t = 0; t < T; ++t) mean += a.lengths[t * L + k] / T;
    for (int t = 0; t < T; ++t) {
      d.length = std::max(d.length, std::abs(b.lengths[t * L + k] - mean));
      for (int c = 0; c < 3; ++c) {
        const size_t i = (static_cast<size_t>(t) * L + k) * 3 + c;
        d.direction = std::max<double>(d.direction, std::abs(a.directions[i] - b.directions[i]));
      }
    }
  }
  return d;
}

}  // namespace motionfork::testing
