// Missing-value masks (no LibTorch): simulated occlusions for experiments, and masks from a
// user's spec for `motionfork impute --mask`. Masks are bytes, 1 = missing, laid out like the
// values they cover.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

// count windows of `values` values each: exactly round(share * values) random values missing in
// every window (at least one value stays observed), reproducible for a seed.
std::vector<uint8_t> RandomOcclusion(int count, int values, double share, uint64_t seed);

// Missing joints (skeleton joint indices, not the root) over every frame of `count` windows of
// `frames` frames in the root-relative layout without the root (3 values per non-root joint).
std::vector<uint8_t> JointOcclusion(int count, int frames, int num_joints,
                                    const std::vector<int>& joints);

// A mask over a motion [T, J, 3] from a spec, one of:
//   random:SHARE            a share (0..1) of every value, at random (seed)
//   joints:A,B,...          these joints in every frame
//   joints:A,B@FIRST-LAST   these joints in frames FIRST..LAST (0-based, inclusive)
//   FILE.npy                a joints x frames mask: [T, J] (a joint's three values) or [T, J, 3],
//                           non-zero = missing, on the motion's joints after mapping
// Throws std::invalid_argument naming the unknown joint (and listing the skeleton's), the root
// (poses are root-relative: it cannot be missing), frames outside 0..T-1, or a mask file of
// another shape (FormatError for an unreadable one).
std::vector<uint8_t> MaskFromSpec(const std::string& spec, const Skeleton& skeleton, int frames,
                                  uint64_t seed);

}  // namespace motionfork
