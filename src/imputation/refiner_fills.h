// The imputation refiner's inputs over a whole motion (no LibTorch): the classical fills of its
// missing values (interpolation_fill.h: cubic spline, linear, rigid limb; the fallback pose where
// a value is never observed) as root-relative coordinates without the root, [T, N] with N = 3
// per non-root joint, the mask in the same layout, and each value's distance in frames to the
// nearest observed value of its coordinate before and after it (0 where observed; capped at
// kRefinerGapCap, which also stands for "none"). Several windows of the same length can be held
// one after the other (AppendRefinerFills).
#pragma once

#include <cstdint>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

constexpr float kRefinerGapCap = 64;
// The refiner's correction counts d^2 / (d^2 + g^2) at d frames from the nearest observed value
// (HgvaeTensors::Refined): a tenth at 1 frame, half at 3, 0.9 at 9.
constexpr float kRefinerGateFrames = 3;

struct RefinerFills {
  int frames = 0;                            // per window
  std::vector<float> spline, linear, rigid;  // [T, N], metres, root-relative
  std::vector<uint8_t> mask;                 // [T, N], 1 = missing
  std::vector<float> before, after;          // [T, N], frames to the nearest observed value
};

// Appends `f`'s window to `all` (the same number of frames in each).
void AppendRefinerFills(const RefinerFills& f, RefinerFills* all);

// positions [T, J, 3] (root observed in every frame), missing [T, J, 3]; fallback [J, 3]
// root-relative (the training mean pose).
RefinerFills MakeRefinerFills(const Skeleton& skeleton, const std::vector<float>& positions,
                              const std::vector<uint8_t>& missing,
                              const std::vector<float>& fallback);

}  // namespace motionfork
