#include "render/scene.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace motionfork::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

using Vec3 = std::array<double, 3>;

double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Side from a joint name when the skeleton lists no left/right pairs (raw BVH files):
// "Hand_L", "hand.l", "LeftArm", "left_knee", "LHip" are left.
Side SideFromName(const std::string& name) {
  const std::string low = Lower(name);
  for (const auto& [side, word, letter] :
       {std::tuple{Side::kLeft, "left", 'l'}, std::tuple{Side::kRight, "right", 'r'}}) {
    if (low.find(word) != std::string::npos) return side;
    if (EndsWith(low, std::string("_") + letter) || EndsWith(low, std::string(".") + letter)) {
      return side;
    }
    if (name.size() > 1 && std::tolower(static_cast<unsigned char>(name[0])) == letter &&
        std::isupper(static_cast<unsigned char>(name[0])) &&
        std::isupper(static_cast<unsigned char>(name[1]))) {
      return side;
    }
  }
  return Side::kCentre;
}

std::vector<Side> JointSides(const Skeleton& s) {
  std::vector<Side> sides(s.num_joints(), Side::kCentre);
  if (s.is_anonymous()) return sides;
  if (s.left_right_pairs().empty()) {
    for (int j = 0; j < s.num_joints(); ++j) sides[j] = SideFromName(s.joint_name(j));
    return sides;
  }
  for (const auto& [l, r] : s.left_right_pairs()) {
    sides[l] = Side::kLeft;
    sides[r] = Side::kRight;
  }
  return sides;
}

// The deepest unpaired joint (the head end of the spine chain), or -1.
int FindHead(const Skeleton& s, const std::vector<Side>& sides) {
  if (s.is_anonymous()) return -1;
  std::vector<int> depth(s.num_joints(), 0);
  int head = -1;
  for (int j = 1; j < s.num_joints(); ++j) {
    depth[j] = depth[s.parent(j)] + 1;
    if (sides[j] == Side::kCentre && depth[j] >= 2 && (head < 0 || depth[j] > depth[head]))
      head = j;
  }
  return head;
}

Vec3 At(const float* pose, int j) { return {pose[3 * j], pose[3 * j + 1], pose[3 * j + 2]}; }

void Validate(const Prediction& p) {
  if (!p.skeleton) throw std::invalid_argument("render: the prediction has no skeleton");
  if (p.k < 1)
    throw std::invalid_argument("render: expected at least one sample, got " + std::to_string(p.k));
  if (p.t_his < 0 || p.t_pred < 0 || p.frames() < 1) {
    throw std::invalid_argument(
        "render: expected t_his >= 0, t_pred >= 0 and at least one frame, got t_his " +
        std::to_string(p.t_his) + ", t_pred " + std::to_string(p.t_pred));
  }
  if (!(p.fps > 0))
    throw std::invalid_argument("render: expected fps > 0, got " + std::to_string(p.fps));
  const size_t expected = static_cast<size_t>(p.k) * p.frames() * p.joints() * 3;
  if (p.positions.size() != expected) {
    throw std::invalid_argument("render: expected " + std::to_string(expected) + " positions ([" +
                                std::to_string(p.k) + ", " + std::to_string(p.frames()) + ", " +
                                std::to_string(p.joints()) + ", 3]), got " +
                                std::to_string(p.positions.size()));
  }
  if (!p.samples.empty() && static_cast<int>(p.samples.size()) != p.k) {
    throw std::invalid_argument("render: expected " + std::to_string(p.k) +
                                " sample validity entries, got " +
                                std::to_string(p.samples.size()));
  }
  for (size_t i = 0; i < p.positions.size(); ++i) {
    if (!std::isfinite(p.positions[i])) {
      const size_t per_frame = static_cast<size_t>(p.joints()) * 3;
      const size_t frame = i / per_frame;
      throw std::invalid_argument("render: sample " + std::to_string(frame / p.frames()) +
                                  ", frame " + std::to_string(frame % p.frames()) + ", joint '" +
                                  p.skeleton->joint_name(static_cast<int>(i % per_frame / 3)) +
                                  "': expected a finite position, got " +
                                  std::to_string(p.positions[i]));
    }
  }
}

std::vector<char> FixedJoints(const Skeleton& s, const std::vector<std::string>& fixed_parts) {
  std::vector<char> fixed(s.num_joints(), 0);
  if (fixed_parts.empty()) return fixed;
  const Partition& partition = s.GetPartition();
  for (const std::string& name : fixed_parts) {
    const auto it = std::find_if(partition.parts.begin(), partition.parts.end(),
                                 [&](const BodyPart& part) { return part.name == name; });
    if (it == partition.parts.end()) {
      std::string known;
      for (const BodyPart& part : partition.parts) known += (known.empty() ? "" : ", ") + part.name;
      throw std::invalid_argument("render: fixed part '" + name + "' is not a part of skeleton '" +
                                  s.name() + "' (partition '" + partition.name + "': " + known +
                                  ")");
    }
    for (int j : it->joints) fixed[j] = 1;
  }
  return fixed;
}

}  // namespace

SignedAxis ParseSignedAxis(const std::string& text) {
  std::string t = Lower(text);
  SignedAxis a;
  if (!t.empty() && (t[0] == '+' || t[0] == '-')) {
    a.sign = t[0] == '-' ? -1 : 1;
    t = t.substr(1);
  }
  if (t == "x" || t == "y" || t == "z") {
    a.axis = t[0] - 'x';
    return a;
  }
  throw std::invalid_argument(
      "expected an axis x, y or z with an optional sign (e.g. 'y', '-z'), got '" + text + "'");
}

std::string ToString(SignedAxis a) {
  return std::string(a.sign < 0 ? "-" : "+") + char('x' + a.axis);
}

Prediction PredictionFromMotion(const Motion& motion) {
  Prediction p;
  p.k = 1;
  p.t_his = 0;
  p.t_pred = motion.num_frames();
  p.fps = motion.fps();
  p.skeleton = motion.skeleton_ptr();
  p.positions = motion.positions();
  return p;
}

Scene BuildScene(const Prediction& p, const SceneOptions& options) {
  Validate(p);
  const Skeleton& s = *p.skeleton;
  const int J = s.num_joints(), T = p.frames();
  Scene scene;
  scene.skeleton = p.skeleton;
  scene.fps = p.fps;
  scene.k = p.k;
  scene.t_his = p.t_his;
  scene.t_pred = p.t_pred;
  scene.samples = p.samples;
  scene.fixed_parts = p.fixed_parts;
  scene.sides = JointSides(s);
  scene.fixed = FixedJoints(s, p.fixed_parts);
  scene.head = FindHead(s, scene.sides);

  // A root with one child is a placement node (e.g. Bandai's ground-level joint_Root), not a body
  // joint: its bone is not drawn and poses are centred on its child.
  std::vector<int> children(J, 0);
  for (int j = 1; j < J; ++j) ++children[s.parent(j)];
  scene.drawn.assign(J, s.is_anonymous() ? 0 : 1);
  scene.drawn[0] = 0;
  if (J > 1 && children[0] == 1 && !s.is_anonymous()) {
    for (int j = 1; j < J; ++j) {
      if (s.parent(j) == 0) {
        scene.pelvis = j;
        scene.drawn[j] = 0;
      }
    }
  }

  scene.visible.assign(J, 0);
  bool any_bone = false;
  for (int j = 1; j < J; ++j) {
    if (scene.drawn[j]) scene.visible[j] = scene.visible[s.parent(j)] = 1, any_bone = true;
  }
  if (scene.head >= 0) scene.visible[scene.head] = 1;
  if (!any_bone) scene.visible.assign(J, 1);

  // Anchor frames: the history (a plain motion: its first second); the last one is the origin.
  const int anchor_end = p.t_his > 0 ? p.t_his : std::min(T, std::max(1, static_cast<int>(p.fps)));
  const int origin_frame = p.t_his > 0 ? p.t_his - 1 : 0;
  const float* sample0 = p.positions.data();
  auto frame = [&](int t) { return sample0 + static_cast<size_t>(t) * J * 3; };

  // Up: the axis along which the head is above the pelvis; without a head, the axis of largest
  // spread, positive.
  if (options.up) {
    scene.up = *options.up;
  } else {
    Vec3 v{0, 0, 0};
    for (int t = 0; t < anchor_end; ++t) {
      const float* f = frame(t);
      for (int a = 0; a < 3; ++a) {
        if (scene.head >= 0) {
          v[a] += f[3 * scene.head + a] - f[3 * scene.pelvis + a];
        } else {
          float lo = f[a], hi = f[a];
          for (int j = 1; j < J; ++j)
            lo = std::min(lo, f[3 * j + a]), hi = std::max(hi, f[3 * j + a]);
          v[a] += hi - lo;
        }
      }
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (std::abs(v[a]) > std::abs(v[axis])) axis = a;
    }
    scene.up = {axis, v[axis] < 0 ? -1 : 1};
  }
  Vec3 up{0, 0, 0};
  up[scene.up.axis] = scene.up.sign;

  // Left: mean of the left joints minus mean of the right joints, made horizontal.
  Vec3 left{0, 0, 0};
  int n_left = 0, n_right = 0;
  for (int j = 0; j < J; ++j) {
    n_left += scene.sides[j] == Side::kLeft;
    n_right += scene.sides[j] == Side::kRight;
  }
  if (n_left > 0 && n_right > 0) {
    for (int t = 0; t < anchor_end; ++t) {
      for (int j = 0; j < J; ++j) {
        if (scene.sides[j] == Side::kCentre) continue;
        const double w = scene.sides[j] == Side::kLeft ? 1.0 / n_left : -1.0 / n_right;
        for (int a = 0; a < 3; ++a) left[a] += w * frame(t)[3 * j + a];
      }
    }
  }
  const double along_up = Dot(left, up);
  for (int a = 0; a < 3; ++a) left[a] -= along_up * up[a];
  double norm = std::sqrt(Dot(left, left));
  if (norm < 1e-9) {
    left = {0, 0, 0};
    left[(scene.up.axis + 1) % 3] = 1;
    norm = 1;
  }
  for (double& c : left) c /= norm;
  const Vec3 facing = Cross(left, up);

  const Vec3 origin = At(frame(origin_frame), scene.pelvis);
  scene.body.resize(p.positions.size());
  float ground = 0;
  bool first = true;
  for (size_t i = 0; i < p.positions.size(); i += 3) {
    const Vec3 d{p.positions[i] - origin[0], p.positions[i + 1] - origin[1],
                 p.positions[i + 2] - origin[2]};
    scene.body[i] = static_cast<float>(Dot(d, left));
    scene.body[i + 1] = static_cast<float>(Dot(d, up));
    scene.body[i + 2] = static_cast<float>(Dot(d, facing));
    if (scene.visible[i / 3 % J] && (first || scene.body[i + 1] < ground)) {
      ground = scene.body[i + 1];
      first = false;
    }
  }
  for (size_t i = 1; i < scene.body.size(); i += 3) scene.body[i] -= ground;
  return scene;
}

void ValidateCamera(const Camera& camera) {
  if (!std::isfinite(camera.azimuth_deg)) {
    throw std::invalid_argument("camera azimuth_deg: expected a finite angle, got " +
                                std::to_string(camera.azimuth_deg));
  }
  if (!(camera.elevation_deg >= -89 && camera.elevation_deg <= 89)) {
    throw std::invalid_argument("camera elevation_deg: expected -89..89 degrees, got " +
                                std::to_string(camera.elevation_deg));
  }
}

void Project(const float* pose, int joints, const Camera& camera, std::vector<ScreenPoint>* out) {
  const double a = camera.azimuth_deg * kPi / 180, e = camera.elevation_deg * kPi / 180;
  // Unit vectors in the body frame: c toward the camera, r screen right (horizontal), u = c x r
  // screen up; the camera at azimuth 0, elevation 0 sees x to the right and y up.
  const Vec3 c{std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a)};
  const Vec3 r{std::cos(a), 0, -std::sin(a)};
  const Vec3 u = Cross(c, r);
  out->resize(joints);
  for (int j = 0; j < joints; ++j) {
    const Vec3 p = At(pose, j);
    (*out)[j] = {static_cast<float>(Dot(p, r)), static_cast<float>(Dot(p, u)),
                 static_cast<float>(Dot(p, c))};
  }
}

}  // namespace motionfork::render
