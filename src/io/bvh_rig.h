// Motion on a BVH file's own rig (io/bvh.h, BvhRig): forward kinematics of its channel values, a
// joint's local rotation as its own channels' Euler angles, and the file's text with new frames.
// What writing futures back onto a user's skeleton needs (pipeline/export_on_rig.h).
#pragma once

#include <string>
#include <vector>

#include "io/bvh.h"

namespace motionfork {

// Every node's world rotation (row-major 3x3, the file's axes) and position (file units) for one
// frame of channel values.
struct BvhRigPose {
  std::vector<double> rotation;  // [nodes, 9]
  std::vector<double> position;  // [nodes, 3]
  const double* R(int node) const { return rotation.data() + 9 * node; }
  const double* p(int node) const { return position.data() + 3 * node; }
};
BvhRigPose RigForwardKinematics(const BvhRig& rig, const double* values);

// The local rotation (row-major 3x3) of `node`'s rotation channels for a frame's `values`.
void RigLocalRotation(const BvhRig::Node& node, const double* values, double* r);

// Sets `node`'s rotation channels in `values` (a frame) to angles composing `r`, choosing of the
// equivalent angle triples the one nearest the values already there (no 360-degree jumps between
// frames). Returns false, leaving them, when the node lacks three rotation channels about
// distinct axes.
bool SetRigLocalRotation(const BvhRig::Node& node, const double* r, double* values);

// The BVH text of `rig`'s hierarchy (names, offsets, channels as in the file) with `values`
// [frames, rig.num_channels] at `frame_time` seconds; numbers with `decimals` digits.
std::string BvhRigText(const BvhRig& rig, const std::vector<double>& values, double frame_time,
                       int decimals = 6);

}  // namespace motionfork
