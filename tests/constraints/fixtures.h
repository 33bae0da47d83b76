// Fixtures for the constraint tests: the shipped constraint sets and skeletons, hand-made
// neutral poses (metres; x = the body's left, y = up, z = forward), random poses, and the
// "impossible pose" transforms, which work on any pose in any global orientation because they
// build their axes from the pose itself.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "core/skeleton.h"

namespace motionfork::testing {

using Pose = std::vector<float>;  // [J, 3] metres

inline SkeletonConfig ShippedSkeleton(const std::string& name) {
  return LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", name));
}

inline ConstraintSetSpec ShippedConstraints(const std::string& name) {
  return LoadConstraintConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "constraints", name));
}

inline ConstraintSet ShippedSet(const std::string& name, const Skeleton& skeleton) {
  return ConstraintSet::Build(ShippedConstraints(name), skeleton);
}

inline Pose PoseByName(const Skeleton& s, const std::map<std::string, Eigen::Vector3f>& at) {
  Pose p(static_cast<size_t>(s.num_joints()) * 3, 0.0f);
  for (const auto& [name, x] : at) {
    const int j = s.Index(name);
    for (int a = 0; a < 3; ++a) p[3 * j + a] = x[a];
  }
  return p;
}

// Standing, arms hanging, knees slightly bent; H36M's "Neck" is the nose, in front of the face.
inline Pose H36mNeutral(const Skeleton& s) {
  return PoseByName(s, {{"Hips", {0, 1.00f, 0}},
                        {"RHip", {-0.13f, 0.98f, 0}},
                        {"RKnee", {-0.13f, 0.55f, 0.03f}},
                        {"RFoot", {-0.13f, 0.10f, -0.02f}},
                        {"LHip", {0.13f, 0.98f, 0}},
                        {"LKnee", {0.13f, 0.55f, 0.03f}},
                        {"LFoot", {0.13f, 0.10f, -0.02f}},
                        {"Spine", {0, 1.23f, -0.01f}},
                        {"Thorax", {0, 1.48f, 0}},
                        {"Neck", {0, 1.58f, 0.10f}},
                        {"Head", {0, 1.72f, 0.01f}},
                        {"LShoulder", {0.17f, 1.45f, 0}},
                        {"LElbow", {0.19f, 1.17f, -0.02f}},
                        {"LWrist", {0.20f, 0.92f, 0.04f}},
                        {"RShoulder", {-0.17f, 1.45f, 0}},
                        {"RElbow", {-0.19f, 1.17f, -0.02f}},
                        {"RWrist", {-0.20f, 0.92f, 0.04f}}});
}

inline Pose HumanEvaNeutral(const Skeleton& s) {
  return PoseByName(s, {{"Pelvis", {0, 1.00f, 0}},
                        {"Thorax", {0, 1.45f, 0}},
                        {"LShoulder", {0.17f, 1.42f, 0}},
                        {"LElbow", {0.19f, 1.14f, -0.02f}},
                        {"LWrist", {0.20f, 0.89f, 0.04f}},
                        {"RShoulder", {-0.17f, 1.42f, 0}},
                        {"RElbow", {-0.19f, 1.14f, -0.02f}},
                        {"RWrist", {-0.20f, 0.89f, 0.04f}},
                        {"LHip", {0.12f, 0.97f, 0}},
                        {"LKnee", {0.12f, 0.55f, 0.03f}},
                        {"LAnkle", {0.12f, 0.10f, -0.02f}},
                        {"RHip", {-0.12f, 0.97f, 0}},
                        {"RKnee", {-0.12f, 0.55f, 0.03f}},
                        {"RAnkle", {-0.12f, 0.10f, -0.02f}},
                        {"Head", {0, 1.68f, 0.02f}}});
}

inline Eigen::Vector3f At(const Skeleton& s, const Pose& p, const std::string& joint) {
  const int j = s.Index(joint);
  return {p[3 * j], p[3 * j + 1], p[3 * j + 2]};
}

// The body's own axes, from the hips and a point high on the spine.
struct BodyAxes {
  Eigen::Vector3f left, up, forward;
};
inline BodyAxes Axes(const Skeleton& s, const Pose& p, const std::string& left_hip,
                     const std::string& right_hip, const std::string& pelvis,
                     const std::string& upper) {
  BodyAxes a;
  a.left = (At(s, p, left_hip) - At(s, p, right_hip)).normalized();
  a.up = At(s, p, upper) - At(s, p, pelvis);
  a.up = (a.up - a.up.dot(a.left) * a.left).normalized();
  a.forward = a.left.cross(a.up);
  return a;
}

// Rotates the named joints about the axis through `pivot` (right-hand rule), degrees.
inline void Rotate(const Skeleton& s, Pose* p, const std::vector<std::string>& joints,
                   const Eigen::Vector3f& pivot, const Eigen::Vector3f& axis, float degrees) {
  const Eigen::Matrix3f r =
      Eigen::AngleAxisf(degrees * static_cast<float>(M_PI) / 180.0f, axis.normalized())
          .toRotationMatrix();
  for (const std::string& name : joints) {
    const int j = s.Index(name);
    Eigen::Map<Eigen::Vector3f> x(p->data() + 3 * j);
    x = pivot + r * (Eigen::Vector3f(x) - pivot);
  }
}

// Angles and statuses of one pose.
struct PoseCheck {
  std::vector<float> angles;
  std::vector<AngleStatus> status;
  bool Fires(const ConstraintSet& set, const std::string& name) const {
    const int c = set.Find(name);
    return c >= 0 && IsViolation(status[c]);
  }
  std::vector<std::string> Fired(const ConstraintSet& set) const {
    std::vector<std::string> out;
    for (int c = 0; c < set.num_constraints(); ++c) {
      if (status[c] != AngleStatus::kInside) out.push_back(set.constraint(c).name);
    }
    return out;
  }
};
inline PoseCheck CheckPose(const ConstraintSet& set, const Pose& p) {
  PoseCheck r;
  r.angles.resize(set.num_constraints());
  r.status.resize(set.num_constraints());
  AngleChecker(set).Run(p.data(), 1, r.angles.data(), r.status.data());
  return r;
}

// Poses scattered around `base`: every coordinate moved by N(0, sigma) metres.
inline std::vector<float> RandomPoses(const Pose& base, int count, float sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, sigma);
  std::vector<float> out;
  out.reserve(base.size() * count);
  for (int i = 0; i < count; ++i) {
    for (float x : base) out.push_back(x + n(rng));
  }
  return out;
}

// The mirror image of a pose: reflected through the x = 0 plane and with left/right joints swapped
// (what a left-handed copy of the same body would look like).
inline Pose Mirrored(const Skeleton& s, const Pose& p) {
  Pose out(p.size());
  for (int j = 0; j < s.num_joints(); ++j) {
    const int m = s.Mirror(j);
    out[3 * j] = -p[3 * m];
    out[3 * j + 1] = p[3 * m + 1];
    out[3 * j + 2] = p[3 * m + 2];
  }
  return out;
}

}  // namespace motionfork::testing
