// BVH writing: any motion of positions on a skeleton with parents, as the joint rotations on a
// rest pose that core/pose_fitting.h fits, so animation tools (Blender, Maya, MotionBuilder)
// open it and ReadBvhFile gives the positions back (bone lengths fixed to their means).
//
// File layout: joints depth-first, children in skeleton order (for a skeleton that is already
// depth-first, as every shipped one, the file's joint order is the skeleton's). The root has
// "Xposition Yposition Zposition" and three rotation channels; other joints three rotation
// channels, preceded by three position channels when the fit translates them (children of a
// branching joint that does not move rigidly); every joint without children ends in an End Site
// half as long as its bone, along it. Rotation channels compose as ReadBvhFile reads them (in the
// listed order, intrinsic: "Zrotation Xrotation Yrotation" is R = Rz Rx Ry), degrees, and are
// continuous from frame to frame (of the two Euler solutions, the one nearer the previous frame,
// unwrapped past +-180 degrees; at gimbal lock the first angle keeps its previous value).
#pragma once

#include <array>
#include <string>

#include "core/motion.h"
#include "core/pose_fitting.h"

namespace motionfork {

struct BvhWriteOptions {
  // File length unit in metres, as BvhOptions::scale_to_metres: 0.01 writes centimetres (what
  // ReadBvhFile and most motion-capture tools assume), 1 writes metres.
  double scale_to_metres = 0.01;
  // Axis order of every joint's rotation channels: a permutation of "XYZ", e.g. "ZXY" (Bandai and
  // most mocap exports) or "ZYX" (CMU).
  std::string rotation_order = "ZXY";
  // Digits after the decimal point of every number (lengths in file units, angles in degrees;
  // trailing zeros are dropped). 6 keeps the round trip within 1e-6 m for human-sized bodies.
  int decimals = 6;
  // Rest pose and rotation fit (branch tolerance, shortest bone).
  PoseFitOptions fit;
};

// Throws std::invalid_argument naming the field, its value and the rule it breaks.
void ValidateBvhWriteOptions(const BvhWriteOptions& options);

// All-or-nothing write (io/file_util.h). Throws std::invalid_argument for bad options, a joint
// name a BVH file cannot hold (empty, whitespace, braces) or a motion FitPose rejects (no limb
// structure, a bone of zero length, naming the frame); FormatError naming the file when it cannot
// be written.
void WriteBvh(const std::string& path, const Motion& motion, const BvhWriteOptions& options = {});

// The text WriteBvh writes.
std::string BvhText(const Motion& motion, const BvhWriteOptions& options = {});

// Euler angles, degrees, of a rotation (row-major 3x3) for an axis order: order "ZXY" gives
// (a, b, c) with R = Rz(a) Rx(b) Ry(c). Of the two solutions, the one nearest `previous`
// (degrees) after unwrapping each angle by multiples of 360 to within 180 of it; at gimbal lock
// (middle angle +-90) the first angle is previous[0]. Throws std::invalid_argument for an order
// that is not a permutation of "XYZ".
std::array<double, 3> EulerDegrees(const double* rotation, const std::string& order,
                                   const std::array<double, 3>& previous = {0, 0, 0});

}  // namespace motionfork
