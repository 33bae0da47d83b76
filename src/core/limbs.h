// Positions <-> (unit limb directions, bone lengths).
//
// A limb is the bone from a joint's parent to the joint, one per non-root joint. Directions are
// the flow prior's input; bone lengths let predictions be re-targeted to another body.
#pragma once

#include <vector>

#include "core/motion.h"

namespace motionfork {

struct Limbs {
  int num_frames = 0;
  int num_limbs = 0;              // J - 1; limb k ends at joint k + 1
  std::vector<float> root;        // [T, 3] root position, metres
  std::vector<float> directions;  // [T, J-1, 3] unit vectors (joint - parent) / |joint - parent|
  std::vector<float> lengths;     // [T, J-1] metres
};

// Throws std::invalid_argument naming the frame and joint when a bone is shorter than
// min_length metres (its direction would be undefined).
Limbs ToLimbs(const Motion& motion, float min_length = 1e-6f);

// Inverse of ToLimbs: forward kinematics along the skeleton. Directions are used as given (they
// are normalised first, so any non-zero vector works). Sizes must match the skeleton.
Motion FromLimbs(std::shared_ptr<const Skeleton> skeleton, double fps, const Limbs& limbs);

}  // namespace motionfork
