// Caller-supplied position arrays as Motions (positions.h).
#include "positions.h"

#include <stdexcept>

#include "core/skeleton.h"

namespace motionfork {

int FramesOf(const std::vector<float>& positions, int joints, const std::string& who) {
  const size_t frame = static_cast<size_t>(joints) * 3;
  if (positions.empty() || positions.size() % frame != 0) {
    throw std::invalid_argument(who + ": expected [T, " + std::to_string(joints) +
                                ", 3] positions, a non-zero multiple of " + std::to_string(frame) +
                                " values, got " + std::to_string(positions.size()) + " values");
  }
  return static_cast<int>(positions.size() / frame);
}

Motion MotionFromPositions(std::shared_ptr<const Skeleton> skeleton, double fps,
                           const std::vector<float>& positions, const std::string& who) {
  FramesOf(positions, skeleton->num_joints(), who);
  try {
    return Motion(std::move(skeleton), fps, positions);
  } catch (const std::invalid_argument& e) {  // a NaN/Inf value or a bad fps: name the caller
    std::string what = e.what();
    if (what.rfind("Motion: ", 0) == 0) what = what.substr(8);
    throw std::invalid_argument(who + ": " + what);
  }
}

Motion MotionFromPositions(const std::vector<std::string>& joint_names,
                           const std::vector<int>& parents, double fps,
                           const std::vector<float>& positions, const std::string& who) {
  if (joint_names.empty() || parents.size() != joint_names.size()) {
    throw std::invalid_argument(who + ": expected a parent per joint (" +
                                std::to_string(joint_names.size()) + " joints), got " +
                                std::to_string(parents.size()) + " parents");
  }
  std::shared_ptr<const Skeleton> skeleton;
  try {
    skeleton =
        std::make_shared<const Skeleton>(Skeleton::FromParents("motion", joint_names, parents));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(who + ": " + e.what());
  }
  return MotionFromPositions(std::move(skeleton), fps, positions, who);
}

}  // namespace motionfork
