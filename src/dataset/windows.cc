#include "dataset/windows.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace motionfork {

int64_t CountSlidingWindows(int frames, int length, int stride, bool include_last) {
  if (length < 1 || stride < 1) {
    throw std::invalid_argument("windows: expected length >= 1 and stride >= 1, got " +
                                std::to_string(length) + " and " + std::to_string(stride));
  }
  const int64_t last_start = static_cast<int64_t>(frames) - length - (include_last ? 0 : 1);
  if (last_start < 0) return 0;
  return last_start / stride + 1;
}

std::vector<Window> SlidingWindows(const std::vector<int>& clip_frames, int length, int stride,
                                   bool include_last) {
  std::vector<Window> out;
  for (size_t c = 0; c < clip_frames.size(); ++c) {
    const int64_t n = CountSlidingWindows(clip_frames[c], length, stride, include_last);
    for (int64_t k = 0; k < n; ++k)
      out.push_back(Window{static_cast<int>(c), static_cast<int>(k * stride)});
  }
  return out;
}

RandomWindowSampler::RandomWindowSampler(std::vector<int> clip_frames, int length, uint64_t seed)
    : clip_frames_(std::move(clip_frames)), length_(length), rng_(seed) {
  if (length < 1) {
    throw std::invalid_argument("RandomWindowSampler: expected length >= 1, got " +
                                std::to_string(length));
  }
  cumulative_.reserve(clip_frames_.size());
  for (int f : clip_frames_) {
    total_ += std::max(0, f - length + 1);
    cumulative_.push_back(total_);
  }
  if (total_ == 0) {
    throw std::invalid_argument("RandomWindowSampler: no clip has the " + std::to_string(length) +
                                " frames one window needs");
  }
}

Window RandomWindowSampler::Next() {
  std::uniform_int_distribution<int64_t> pick(0, total_ - 1);
  const int64_t k = pick(rng_);
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), k);
  const int clip = static_cast<int>(it - cumulative_.begin());
  const int64_t before = clip > 0 ? cumulative_[clip - 1] : 0;
  return Window{clip, static_cast<int>(k - before)};
}

}  // namespace motionfork
