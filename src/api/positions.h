// Caller-supplied [T, J, 3] position arrays as Motions, with errors named as the caller's.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/motion.h"

namespace motionfork {

// The frame count of `positions` laid out [T, joints, 3]; std::invalid_argument naming `who`
// when it is empty or not a whole number of frames.
int FramesOf(const std::vector<float>& positions, int joints, const std::string& who);

// `positions` as a Motion of `skeleton` at `fps`: the size checked as FramesOf does, and a NaN/Inf
// value (or a bad fps) rethrown as "<who>: <what>", naming the frame and joint.
Motion MotionFromPositions(std::shared_ptr<const Skeleton> skeleton, double fps,
                           const std::vector<float>& positions, const std::string& who);

// The same for a caller's own skeleton (names and parents), checked to have a parent per joint.
Motion MotionFromPositions(const std::vector<std::string>& joint_names,
                           const std::vector<int>& parents, double fps,
                           const std::vector<float>& positions, const std::string& who);

}  // namespace motionfork
