// What the pictures draw, independent of the output format: a prediction (or a plain motion) put
// into a body-aligned frame, with every joint's drawing role (side, fixed part, head).
//
// The body frame: x = the body's left (seen from the front, the viewer's right), y = up, z = the
// direction the body faces (toward a viewer standing in front of it); metres; the ground (the
// lowest joint over all samples and frames) at y = 0 and the pelvis of the anchor frame (the last
// history frame, or frame 0 of a plain motion) at x = z = 0. The facing direction is the mean
// left-minus-right direction of the anchor frames, turned a quarter around the up axis; the data
// is assumed right-handed (BVH and Human3.6M are).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/motion.h"
#include "core/skeleton.h"
#include "io/prediction_file.h"

namespace motionfork::render {

// +X, -Y, ... of the data's coordinates.
struct SignedAxis {
  int axis = 1;  // 0 = x, 1 = y, 2 = z
  int sign = 1;  // +1 or -1
};
// "y", "+z", "-x" (case-insensitive). Throws std::invalid_argument naming the value.
SignedAxis ParseSignedAxis(const std::string& text);
std::string ToString(SignedAxis a);

enum class Side { kCentre, kLeft, kRight };

struct SceneOptions {
  // The data's up axis; nullopt = from the data (the axis along which the head is above the
  // pelvis; Bandai/BVH data is +Y up, Human3.6M exports are +Z up).
  std::optional<SignedAxis> up;
};

// A camera looking at the body frame's origin, orthographic.
struct Camera {
  double azimuth_deg = 30;   // around the up axis: 0 = in front of the body, 90 = at its left side
  double elevation_deg = 8;  // above the horizon, degrees (-89..89)
};

// One projected joint: screen x to the right and y up (metres), depth toward the camera (metres).
struct ScreenPoint {
  float x, y, depth;
};

struct Scene {
  std::shared_ptr<const Skeleton> skeleton;
  double fps = 0;
  int k = 0, t_his = 0, t_pred = 0;  // t_his = 0 for a plain motion (all frames are "future")
  std::vector<float> body;           // [K, T, J, 3] body frame (see above), metres
  std::vector<Side> sides;           // [J]
  std::vector<char> fixed;           // [J] 1 when the joint belongs to a fixed part
  std::vector<char> drawn;           // [J] 1 when the bone joint -> parent is drawn
  // [J] 1 when the joint shows (an end of a drawn bone, the head; every joint when no bone is
  // drawn, e.g. an anonymous skeleton, whose joints are drawn as dots). Scales and the ground
  // come from these joints only.
  std::vector<char> visible;
  int pelvis = 0;  // the joint poses are centred on (the root, or its only child)
  int head = -1;   // the joint drawn with a head circle, -1 when none is known
  std::vector<std::string> fixed_parts;
  std::vector<SampleValidity> samples;  // K entries, or empty (validity unknown)
  SignedAxis up;                        // the data axis used as up

  int frames() const { return t_his + t_pred; }
  int joints() const { return skeleton->num_joints(); }
  // Sample k, frame t: [J, 3].
  const float* pose(int k, int t) const {
    return body.data() + (static_cast<size_t>(k) * frames() + t) * joints() * 3;
  }
};

// Validates the prediction (sizes, finite values, fixed part names) and builds the scene.
// Throws std::invalid_argument with "expected N, got M" or naming the bad sample/frame/part.
Scene BuildScene(const Prediction& p, const SceneOptions& options = {});

// A plain motion as a one-sample prediction without history (t_his = 0, t_pred = T).
Prediction PredictionFromMotion(const Motion& motion);

// Projects body-frame poses ([J, 3]) for a camera; out gets J points.
void Project(const float* pose, int joints, const Camera& camera, std::vector<ScreenPoint>* out);

// Throws std::invalid_argument naming the field when the camera's angles are out of range.
void ValidateCamera(const Camera& camera);

}  // namespace motionfork::render
