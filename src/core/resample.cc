#include "core/resample.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace motionfork {

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
  const size_t stride = static_cast<size_t>(motion.num_joints()) * 3;
  std::vector<float> out(out_frames * stride);
  for (int i = 0; i < out_frames; ++i) {
    const double s = i * ratio;
    int s0 = static_cast<int>(std::floor(s + 1e-9));
    if (s0 > T - 1) s0 = T - 1;
    const int s1 = s0 + 1 < T ? s0 + 1 : s0;
    const double w = s1 == s0 ? 0.0 : std::max(0.0, s - s0);
    const float* a = motion.frame(s0);
    const float* b = motion.frame(s1);
    float* d = out.data() + i * stride;
    for (size_t k = 0; k < stride; ++k) d[k] = static_cast<float>(a[k] + w * (b[k] - a[k]));
  }
  return Motion(motion.skeleton_ptr(), target_fps, std::move(out));
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
  std::vector<float> out(static_cast<size_t>(out_frames) * F);
  for (int i = 0; i < out_frames; ++i) {
    const double s = i / factor;
    const int s0 = std::min(T - 1, static_cast<int>(std::floor(s + 1e-9)));
    const int s1 = std::min(T - 1, s0 + 1);
    const double w = s1 == s0 ? 0.0 : std::max(0.0, s - s0);
    for (size_t k = 0; k < F; ++k) {
      const float a = positions[s0 * F + k], b = positions[s1 * F + k];
      out[i * F + k] = static_cast<float>(a + w * (b - a));
    }
  }
  return out;
}

}  // namespace motionfork
