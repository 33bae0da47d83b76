#include "core/resample.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace motionfork {
namespace {

// Frames [out_frames, F] linearly interpolated in time from positions [T, F] (T >= 1): frame i at
// source time source_time(i), in source frames (past the last frame: the last frame).
template <typename SourceTime>
std::vector<float> InterpolateFrames(const float* positions, int T, size_t F, int out_frames,
                                     SourceTime source_time) {
  std::vector<float> out(static_cast<size_t>(out_frames) * F);
  for (int i = 0; i < out_frames; ++i) {
    const double s = source_time(i);
    const int s0 = std::min(T - 1, static_cast<int>(std::floor(s + 1e-9)));
    const int s1 = std::min(T - 1, s0 + 1);
    const double w = s1 == s0 ? 0.0 : std::max(0.0, s - s0);
    const float* a = positions + static_cast<size_t>(s0) * F;
    const float* b = positions + static_cast<size_t>(s1) * F;
    float* d = out.data() + static_cast<size_t>(i) * F;
    for (size_t k = 0; k < F; ++k) d[k] = static_cast<float>(a[k] + w * (b[k] - a[k]));
  }
  return out;
}

}  // namespace

Motion Resample(const Motion& motion, double target_fps) {
  if (!(target_fps > 0) || !std::isfinite(target_fps)) {
    throw std::invalid_argument("Resample: expected a target frame rate > 0 Hz, got " +
                                std::to_string(target_fps));
  }
  const int T = motion.num_frames();
  if (T == 0 || target_fps == motion.fps()) return motion;
  const double ratio = motion.fps() / target_fps;  // source frames per target frame
  // Small tolerance so that e.g. (T-1)/ratio = 29.9999999 still yields its last frame.
  const int out_frames = static_cast<int>(std::floor((T - 1) / ratio + 1e-9)) + 1;
  return Motion(motion.skeleton_ptr(), target_fps,
                InterpolateFrames(motion.frame(0), T, static_cast<size_t>(motion.num_joints()) * 3,
                                  out_frames, [ratio](int i) { return i * ratio; }));
}

std::vector<float> SlowDown(const std::vector<float>& positions, int joints, double factor) {
  if (!(factor > 0) || !std::isfinite(factor))
    throw std::invalid_argument("SlowDown: expected a factor > 0, got " + std::to_string(factor));
  const size_t F = 3 * static_cast<size_t>(std::max(joints, 0));
  if (F == 0 || positions.size() % F != 0) {
    throw std::invalid_argument("SlowDown: expected positions [T, " + std::to_string(joints) +
                                ", 3], got " + std::to_string(positions.size()) + " values");
  }
  const int T = static_cast<int>(positions.size() / F);
  if (T == 0) return {};
  const int out_frames = static_cast<int>(std::floor((T - 1) * factor + 1e-9)) + 1;
  return InterpolateFrames(positions.data(), T, F, out_frames,
                           [factor](int i) { return i / factor; });
}

}  // namespace motionfork
