// Limits on what a motion file may hold, so that a damaged or hostile file cannot cost unbounded
// memory or time. Every motion reader (BVH, .npy, .csv) refuses a file beyond them with a message
// naming the limit. A human skeleton has tens of joints, dense hand and face rigs a few hundred;
// an hour of capture at 120 Hz is 432,000 frames.
#pragma once

#include <cstdint>

namespace motionfork {

constexpr int kMaxMotionJoints = 1024;
constexpr int64_t kMaxMotionFrames = 10'000'000;  // a day at 120 Hz
// Positions (floats) of one motion: 2^28 = 1 GiB.
constexpr uint64_t kMaxMotionValues = uint64_t{1} << 28;
// Positions of a BVH without channels (every frame the rest pose, stored in no bytes): 64 MiB.
constexpr uint64_t kMaxRestPoseValues = uint64_t{1} << 24;

}  // namespace motionfork
