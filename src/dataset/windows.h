// Protocol windows: fixed-length frame ranges cut from clips.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

namespace motionfork {

// Frames [start, start + length) of clip `clip`.
struct Window {
  int clip = 0;
  int start = 0;
};

// Test windows: starts 0, stride, 2*stride, ... in every clip. With include_last = false a start
// must be strictly below T - length (DLow's evaluation code: range(0, T - length, stride), so a
// clip of exactly `length` frames gives none); with include_last = true, start <= T - length.
std::vector<Window> SlidingWindows(const std::vector<int>& clip_frames, int length, int stride,
                                   bool include_last);

// Number of windows SlidingWindows would return for one clip of `frames` frames.
int64_t CountSlidingWindows(int frames, int length, int stride, bool include_last);

// Random training windows, uniform over every valid (clip, start) pair, reproducible for a seed.
class RandomWindowSampler {
 public:
  // Throws std::invalid_argument when no clip is long enough for one window.
  RandomWindowSampler(std::vector<int> clip_frames, int length, uint64_t seed);
  Window Next();
  // Number of distinct windows the sampler draws from (every start in every clip).
  int64_t num_candidates() const { return total_; }

 private:
  std::vector<int> clip_frames_;
  std::vector<int64_t> cumulative_;  // cumulative_[i] = windows in clips [0, i]
  int length_;
  int64_t total_ = 0;
  std::mt19937_64 rng_;
};

}  // namespace motionfork
