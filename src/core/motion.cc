#include "core/motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace motionfork {

Motion::Motion(std::shared_ptr<const Skeleton> skeleton, double fps, std::vector<float> positions)
    : skeleton_(std::move(skeleton)), fps_(fps), positions_(std::move(positions)) {
  if (!skeleton_) throw std::invalid_argument("Motion: expected a skeleton, got null");
  if (!(fps_ > 0) || !std::isfinite(fps_)) {
    throw std::invalid_argument("Motion: expected a frame rate > 0 Hz, got " +
                                std::to_string(fps_));
  }
  const size_t per_frame = stride();
  if (positions_.size() % per_frame != 0) {
    throw std::invalid_argument("Motion: expected positions [T, " + std::to_string(num_joints()) +
                                ", 3] (a multiple of " + std::to_string(per_frame) +
                                " values), got " + std::to_string(positions_.size()) + " values");
  }
  num_frames_ = static_cast<int>(positions_.size() / per_frame);
  for (size_t i = 0; i < positions_.size(); ++i) {
    if (!std::isfinite(positions_[i])) {
      const size_t t = i / per_frame, j = (i % per_frame) / 3;
      throw std::invalid_argument("Motion: non-finite position at frame " + std::to_string(t) +
                                  ", joint '" + skeleton_->joint_name(static_cast<int>(j)) + "'");
    }
  }
}

Motion Motion::Slice(int begin, int end) const {
  if (begin < 0 || end > num_frames_ || begin > end) {
    throw std::invalid_argument(
        "Motion::Slice: expected 0 <= begin <= end <= " + std::to_string(num_frames_) + ", got [" +
        std::to_string(begin) + ", " + std::to_string(end) + ")");
  }
  std::vector<float> out(positions_.begin() + begin * stride(),
                         positions_.begin() + end * stride());
  return Motion(skeleton_, fps_, std::move(out));
}

BoundingBox ComputeBoundingBox(const Motion& motion) {
  BoundingBox box;
  for (int a = 0; a < 3; ++a) {
    box.min[a] = 0;
    box.max[a] = 0;
  }
  const auto& p = motion.positions();
  if (p.empty()) return box;
  for (int a = 0; a < 3; ++a) box.min[a] = box.max[a] = p[a];
  for (size_t i = 0; i < p.size(); i += 3) {
    for (int a = 0; a < 3; ++a) {
      box.min[a] = std::min(box.min[a], p[i + a]);
      box.max[a] = std::max(box.max[a], p[i + a]);
    }
  }
  return box;
}

Motion RootRelative(const Motion& motion) {
  std::vector<float> out = motion.positions();
  const int J = motion.num_joints();
  for (int t = 0; t < motion.num_frames(); ++t) {
    float* f = out.data() + static_cast<size_t>(t) * J * 3;
    const float root[3] = {f[0], f[1], f[2]};
    for (int j = 0; j < J; ++j) {
      for (int a = 0; a < 3; ++a) f[3 * j + a] -= root[a];
    }
  }
  return Motion(motion.skeleton_ptr(), motion.fps(), std::move(out));
}

std::vector<float> PoseVectorsWithoutRoot(const Motion& motion) {
  const int J = motion.num_joints();
  std::vector<float> out;
  out.reserve(static_cast<size_t>(motion.num_frames()) * (J - 1) * 3);
  for (int t = 0; t < motion.num_frames(); ++t) {
    const float* f = motion.frame(t);
    for (int j = 1; j < J; ++j) {
      for (int a = 0; a < 3; ++a) out.push_back(f[3 * j + a] - f[a]);
    }
  }
  return out;
}

}  // namespace motionfork
