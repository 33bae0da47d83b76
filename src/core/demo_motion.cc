#include "core/demo_motion.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace motionfork {
namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// Body sizes of an adult of about 1.7 m (metres), close to the Bandai actors' skeletons. The
// pelvis and the trunk are rigid as in the Bandai skeleton; offsets in the pelvis frame (+x left,
// +y along the spine, +z forward).
constexpr double kThigh = 0.39, kShin = 0.41, kAnkleHeight = 0.11;
constexpr double kUpperArm = 0.245, kForearm = 0.225;
const Vector3d kHipOffset(0.0647, -0.0219, 0);         // Hips -> UpperLeg_L (x mirrored for _R)
const Vector3d kSpineOffset(0, 0.1574, 0);             // Hips -> Spine
const Vector3d kChestOffset(0, 0.0899, -0.0017);       // Spine -> Chest
const Vector3d kNeckOffset(0, 0.1632, -0.0095);        // Chest -> Neck
const Vector3d kHeadOffset(0, 0.0634, -0.0111);        // Neck -> Head
const Vector3d kShoulderOffset(0.102, 0.127, -0.006);  // Chest -> UpperArm_L (x mirrored for _R)

// Direction in the sagittal plane: down (0, -1, 0) turned forward (+Z) by angle a (radians).
Vector3d Swing(double a, double outward = 0) {
  return Vector3d(outward, -std::cos(a), std::sin(a)).normalized();
}

}  // namespace

Motion MakeDemoWalk(std::shared_ptr<const Skeleton> skeleton, const DemoWalkOptions& o) {
  if (!skeleton) throw std::invalid_argument("MakeDemoWalk: no skeleton");
  if (o.frames < 1)
    throw std::invalid_argument("MakeDemoWalk: frames must be >= 1, got " +
                                std::to_string(o.frames));
  if (!(o.fps > 0) || !std::isfinite(o.fps)) {
    throw std::invalid_argument("MakeDemoWalk: fps must be a finite number > 0, got " +
                                std::to_string(o.fps));
  }
  if (!std::isfinite(o.stride_hz) || !std::isfinite(o.speed) || !std::isfinite(o.heading_deg) ||
      !std::isfinite(o.phase)) {
    throw std::invalid_argument(
        "MakeDemoWalk: stride_hz, speed, heading_deg and phase must be finite");
  }
  static const char* const kJoints[] = {
      "Hips",       "Spine",  "Chest",      "Neck",       "Head",   "UpperLeg_L",
      "LowerLeg_L", "Foot_L", "UpperLeg_R", "LowerLeg_R", "Foot_R", "UpperArm_L",
      "LowerArm_L", "Hand_L", "UpperArm_R", "LowerArm_R", "Hand_R"};
  for (const char* name : kJoints) {
    if (!skeleton->Find(name)) {
      throw std::invalid_argument("MakeDemoWalk: skeleton '" + skeleton->name() +
                                  "' has no joint '" + name +
                                  "'; the demo walk is made for the Bandai protocol skeleton");
    }
  }
  for (const std::string& name : skeleton->joint_names()) {
    if (std::find_if(std::begin(kJoints), std::end(kJoints),
                     [&](const char* k) { return name == k; }) == std::end(kJoints)) {
      throw std::invalid_argument(
          "MakeDemoWalk: skeleton '" + skeleton->name() + "' has joint '" + name +
          "', which the demo walk does not know (Bandai protocol skeleton only)");
    }
  }

  const int J = skeleton->num_joints();
  std::vector<float> positions(static_cast<size_t>(o.frames) * J * 3);
  const double heading = o.heading_deg * kPi / 180;
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(heading, Vector3d::UnitY()).toRotationMatrix();
  for (int t = 0; t < o.frames; ++t) {
    const double time = t / o.fps;
    const double phi = o.phase + 2 * kPi * o.stride_hz * time;
    std::map<std::string, Vector3d> p;  // in the walker's frame: +X left, +Y up, +Z forward
    // The pelvis (and the trunk on it) tilts forward a little: +y turns toward +z.
    const double lean = 0.05 + 0.015 * std::cos(2 * phi);
    const Eigen::Matrix3d pelvis_frame =
        Eigen::AngleAxisd(lean, Vector3d::UnitX()).toRotationMatrix();
    auto body = [&](const Vector3d& offset, int side) {
      return Vector3d(pelvis_frame * Vector3d(side * offset.x(), offset.y(), offset.z()));
    };
    // Legs relative to the pelvis; side s = +1 left, -1 right; the right leg half a cycle later.
    std::map<std::string, Vector3d> leg;
    double lowest = 0;
    for (int s : {+1, -1}) {
      const std::string sfx = s > 0 ? "_L" : "_R";
      const double a = phi + (s > 0 ? 0 : kPi);
      const double thigh = 0.08 + 0.36 * std::sin(a);  // flexion forward, less extension back
      const double knee =
          0.08 + 1.1 * std::pow(std::max(0.0, std::cos(a - 0.5)), 3);  // swing flexion
      const Vector3d hip = body(kHipOffset, s);
      const Vector3d knee_pos = hip + kThigh * Swing(thigh);
      const Vector3d ankle = knee_pos + kShin * Swing(thigh - knee);
      leg["UpperLeg" + sfx] = hip;
      leg["LowerLeg" + sfx] = knee_pos;
      leg["Foot" + sfx] = ankle;
      lowest = std::min(lowest, ankle.y());
    }
    // The pelvis rides on the lower foot; a little sway toward the stance leg.
    const Vector3d pelvis(0.025 * std::sin(phi), kAnkleHeight - lowest, o.speed * time);
    p["Hips"] = pelvis;
    for (const auto& [name, v] : leg) p[name] = pelvis + v;
    p["Spine"] = p["Hips"] + body(kSpineOffset, 1);
    p["Chest"] = p["Spine"] + body(kChestOffset, 1);
    p["Neck"] = p["Chest"] + body(kNeckOffset, 1);
    p["Head"] = p["Neck"] + body(kHeadOffset, 1);
    for (int s : {+1, -1}) {
      const std::string sfx = s > 0 ? "_L" : "_R";
      // Arms swing against the leg of their side; elbows bend more on the forward swing.
      const double a = phi + (s > 0 ? 0 : kPi);
      const double arm = -0.32 * std::sin(a);
      const double elbow = 0.25 + 0.2 * std::max(0.0, -std::sin(a));
      const Vector3d shoulder = p["Chest"] + body(kShoulderOffset, s);
      const Vector3d elbow_pos = shoulder + kUpperArm * Swing(arm, s * 0.12);
      p["UpperArm" + sfx] = shoulder;
      p["LowerArm" + sfx] = elbow_pos;
      p["Hand" + sfx] = elbow_pos + kForearm * Swing(arm + elbow, s * 0.08);
    }
    for (int j = 0; j < J; ++j) {
      const Vector3d w = turn * p.at(skeleton->joint_name(j));
      for (int c = 0; c < 3; ++c)
        positions[(static_cast<size_t>(t) * J + j) * 3 + c] = static_cast<float>(w[c]);
    }
  }
  return Motion(std::move(skeleton), o.fps, std::move(positions));
}

}  // namespace motionfork
