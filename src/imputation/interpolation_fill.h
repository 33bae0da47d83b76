// Classical ways to fill missing joint values over a whole motion, the baselines a learned imputer
// has to beat (no LibTorch): interpolation in time, per coordinate, and a rigid-limb fill that
// keeps bone lengths. Motions are [frames, joints, 3] floats in metres with a mask of the same
// layout (1 = missing); observed values are returned unchanged.
//
// The root is filled in world coordinates, every other joint relative to the root (so that a
// joint missing while the body walks moves with it). A value observed in no frame at all takes the
// fallback pose's ([joints, 3], root-relative; e.g. the training mean); without a fallback that is
// an error naming the joint.
#pragma once

#include <cstdint>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

enum class Interpolation {
  kLinear,       // straight lines between the observed frames around a gap
  kCubicSpline,  // a natural cubic spline through every observed frame of the coordinate
  // Gaps of at most kLocalGapFrames: the polynomial through the observed frames within
  // kLocalReach frames of the gap's edges (at most kLocalNodes on each side; degree up to 7),
  // which follows a smooth motion more closely than the spline over short gaps; longer gaps and the
  // ends as kCubicSpline.
  kLocalPolynomial,
};
constexpr int kLocalGapFrames = 4, kLocalNodes = 4, kLocalReach = 6;

// Each missing value from the observed frames of its coordinate; before the first and after the
// last observed frame, the nearest observed value. Throws std::invalid_argument for mismatched
// sizes, or a coordinate never observed without a fallback.
std::vector<float> InterpolateMissing(const std::vector<float>& positions,
                                      const std::vector<uint8_t>& missing, int joints,
                                      Interpolation kind, const std::vector<float>& fallback = {});

// Joints placed from their parent outward: the missing coordinates of a joint in a frame are those
// of its parent's position plus the bone (parent -> joint) at that frame, the bone's length its
// median over the frames where both ends are observed and its direction interpolated between those
// frames (normalised linear interpolation; the nearest one beyond them). A bone never observed
// takes the fallback pose's length and direction. The root itself: linear interpolation.
std::vector<float> RigidLimbFill(const Skeleton& skeleton, const std::vector<float>& positions,
                                 const std::vector<uint8_t>& missing,
                                 const std::vector<float>& fallback = {});

}  // namespace motionfork
