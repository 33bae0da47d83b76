// Motion: a skeleton, a frame rate and world positions of every joint in every frame.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

class Motion {
 public:
  Motion() = default;
  // positions: [T, J, 3] row-major, metres; fps in Hz (> 0). Every value must be finite.
  // Throws std::invalid_argument on a size mismatch or a non-finite value (naming the frame and
  // joint).
  Motion(std::shared_ptr<const Skeleton> skeleton, double fps, std::vector<float> positions);

  const Skeleton& skeleton() const { return *skeleton_; }
  const std::shared_ptr<const Skeleton>& skeleton_ptr() const { return skeleton_; }
  double fps() const { return fps_; }
  int num_frames() const { return num_frames_; }
  int num_joints() const { return skeleton_ ? skeleton_->num_joints() : 0; }
  double duration_seconds() const { return num_frames_ / fps_; }

  // [T, J, 3] row-major, metres.
  const std::vector<float>& positions() const { return positions_; }
  // Pointer to frame t: [J, 3].
  const float* frame(int t) const { return positions_.data() + static_cast<size_t>(t) * stride(); }
  float* mutable_frame(int t) { return positions_.data() + static_cast<size_t>(t) * stride(); }
  // Pointer to joint j of frame t: [3].
  const float* at(int t, int j) const { return frame(t) + 3 * j; }

  // Frames [begin, end) as a new motion.
  Motion Slice(int begin, int end) const;

 private:
  size_t stride() const { return static_cast<size_t>(num_joints()) * 3; }

  std::shared_ptr<const Skeleton> skeleton_;
  double fps_ = 0;
  int num_frames_ = 0;
  std::vector<float> positions_;
};

// Axis-aligned bounding box of all positions, metres.
struct BoundingBox {
  float min[3];
  float max[3];
};
BoundingBox ComputeBoundingBox(const Motion& motion);

// Root-relative motion: the root joint's position is subtracted from every joint in each frame
// (the root itself becomes the origin).
Motion RootRelative(const Motion& motion);

// Flattened root-relative pose vectors without the root: [T, (J-1)*3], metres. This is the pose
// vector the protocols' metrics use (48 numbers for 17 joints).
std::vector<float> PoseVectorsWithoutRoot(const Motion& motion);

}  // namespace motionfork
