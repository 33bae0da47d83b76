// Keeping a filled motion's bones at their lengths (no LibTorch). Interpolating a joint that turns
// about its parent cuts the chord of its arc: the filled joint comes out too close to the parent.
// Where the bones of a motion are rigid (skeletal motion capture), each bone's length is pinned
// down by the frames where both its ends are observed; moving the filled joints of every frame
// until their bones have those lengths removes that error and leaves the rest of the fill alone.
//
// Motions are [frames, joints, 3] floats with a mask of the same layout (1 = missing). A joint is
// moved only where all three of its coordinates are missing; observed values never change.
#pragma once

#include <cstdint>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

// A bone (parent(j) -> j) as observed: its median length over the frames where both of its ends
// are wholly observed (and apart), and how far from it the lengths stray (90th percentile of
// |length - median|). A bone is rigid when some frame observes it, it is at least kShortestBone
// long and strays at most kRigidSpread: a protocol skeleton's "bone" that skips a joint of the
// source (the Bandai upper arm hangs on the chest, past the clavicle) stretches and is left alone.
constexpr double kShortestBone = 0.005, kRigidSpread = 0.0005;  // metres
struct ObservedBone {
  double length = 0, spread = 0;
  int frames = 0;
  bool rigid() const { return frames > 0 && length >= kShortestBone && spread <= kRigidSpread; }
};
// Indexed by joint (the bone to its parent; the root's is empty).
std::vector<ObservedBone> ObservedBones(const Skeleton& skeleton,
                                        const std::vector<float>& positions,
                                        const std::vector<uint8_t>& missing);

// `filled` with its missing joints moved, frame by frame, towards the nearest placement that gives
// every rigid bone (ObservedBones of filled and missing) its observed length: sweeps of
// projections onto one bone at a time (a bone between two missing joints moves both equally).
// Other bones constrain nothing. Throws std::invalid_argument for mismatched sizes.
std::vector<float> KeepBoneLengths(const Skeleton& skeleton, const std::vector<float>& filled,
                                   const std::vector<uint8_t>& missing, int sweeps = 20);

}  // namespace motionfork
