// How a motion's numbers relate to a model's frame: the length unit (from the body's size), the
// up axis (head above pelvis) and whether the left/right labels agree with the body (knees bend
// forward). Works on a motion already on the model's joints, whose roles (pelvis, left_knee, ...)
// are known (rig/joint_mapping.h, RolesOfSkeleton).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/motion.h"

namespace motionfork {

struct BodyFrameOptions {
  // Metres per file unit the values were read with (0.01 for a BVH read as centimetres, 1 for
  // .npy/.csv): lets the detected unit be named as the file's.
  double read_scale = 1.0;
  // Forced file unit, metres per unit (1 m, 0.01 cm, 0.001 mm, 0.0254 in); 0 = detect.
  double unit = 0;
  // Forced up axis of the values: "y", "z", "x", "-y", "-z", "-x"; "" = detect.
  std::string up;
  // Forced left/right: "as-labelled" or "swapped"; "" = detect.
  std::string left_right;
  // The model's up axis ("y", "z", "-z", ...; its protocol's `up`); "" = keep the motion's own.
  std::string target_up = "y";
};

struct BodyFrame {
  double scale = 1.0;                    // multiply the values by this to get metres
  double unit = 1.0;                     // the file's unit, metres per unit
  int up_axis = 1;                       // the values' axis that points up (0 x, 1 y, 2 z) ...
  int up_sign = 1;                       // ... and its sign
  int target_axis = 1, target_sign = 1;  // the model's up axis, where up_axis is turned to
  bool swapped = false;                  // left/right labels exchanged to agree with the body
  // What was decided from the data (false: forced, or kept as read because the data could not
  // tell; `warnings` then says why).
  bool unit_detected = false, up_detected = false, left_right_detected = false;
  double body_size = 0;  // median leg + trunk length, metres after scaling
  // Mean over frames of how far the knees lie in front of the hip-ankle lines, metres, the front
  // taken from the labels (positive: the labels agree with the body); 0 when unknown.
  double knee_forward = 0;
  std::vector<std::string> warnings;
  // "centimetres, Z up, left/right swapped": how the values were read, for people.
  std::string Describe() const;
  // True when the values are used as read (metres at the read scale, Y up, labels as given).
  bool IsIdentity(double read_scale) const;
};

// Decides the frame of `motion` (values at options.read_scale; missing values marked in
// `missing`, [T, J, 3], or empty), `roles` [J] naming each joint's role ("" for none).
// Throws std::invalid_argument for a bad forced value (naming it and the choices).
BodyFrame DetectBodyFrame(const Motion& motion, const std::vector<uint8_t>& missing,
                          const std::vector<std::string>& roles, const BodyFrameOptions& options);

// The motion in the model's frame: scaled to metres, rotated so that its up axis becomes the
// model's (a proper rotation, handedness kept), left/right partners exchanged when
// `frame.swapped`. `missing` follows the
// exchange when non-empty.
Motion ToModelFrame(const Motion& motion, const BodyFrame& frame,
                    const std::vector<std::string>& roles, std::vector<uint8_t>* missing);

// The way back: model-frame positions (metres, Y up) as the file's values (its unit, axes and
// labels), e.g. futures written for the user's rig. FromModelFrame(ToModelFrame(m)) == m.
Motion FromModelFrame(const Motion& motion, const BodyFrame& frame,
                      const std::vector<std::string>& roles);

// Parses an axis ("y", "+Z", "-x"; case-insensitive) into (axis 0-2, sign); throws naming the
// choices.
std::pair<int, int> ParseUpAxis(const std::string& up);

// Parses a --unit value ("m", "cm", "mm", "in", or "auto"/"" = 0); throws naming the choices.
double ParseLengthUnit(const std::string& unit);

}  // namespace motionfork
