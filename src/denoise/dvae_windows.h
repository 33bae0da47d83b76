// Sequences <-> Motion-DVAE windows (no LibTorch). A window's values are every joint's position
// minus the window's mean root position (metres), so windows do not depend on where the motion
// happens; denoised windows are put back with that offset and blended where they overlap.
#pragma once

#include <array>
#include <vector>

namespace motionfork {

struct WindowCut {
  int sequence = 0;  // index into the caller's sequences
  int start = 0;
  int length = 0;
  std::array<float, 3> root_mean{};  // subtracted from every joint
};

// Windows of `window` frames every `stride` frames (the last one ends at the sequence's end);
// a sequence shorter than `window` (>= 2 frames) is one window of its own length.
std::vector<WindowCut> CutWindows(const std::vector<int>& frames, int window, int stride);

// Window values [length, joints * 3] of positions [frames, joints, 3] (root = joint 0).
std::vector<float> WindowValues(const float* positions, int joints, WindowCut* cut);

// Blends denoised windows back: out[s] gets the weighted mean of every window covering a frame
// (weights min(i + 1, length - i): a window's edges count least). values[w]: [length, joints * 3]
// relative to cuts[w].root_mean.
std::vector<std::vector<float>> BlendWindows(const std::vector<WindowCut>& cuts,
                                             const std::vector<std::vector<float>>& values,
                                             const std::vector<int>& frames, int joints);

}  // namespace motionfork
