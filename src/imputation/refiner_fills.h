// The imputation refiner's inputs over a whole motion (no LibTorch): the classical fills of its
// missing values (interpolation_fill.h: cubic spline, linear, rigid limb; the fallback pose where
// a value is never observed) as root-relative coordinates without the root, [T, N] with N = 3
// per non-root joint, and the mask in the same layout.
#pragma once

#include <cstdint>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

struct RefinerFills {
  int frames = 0;
  std::vector<float> spline, linear, rigid;  // [T, N], metres, root-relative
  std::vector<uint8_t> mask;                 // [T, N], 1 = missing
};

// positions [T, J, 3] (root observed in every frame), missing [T, J, 3]; fallback [J, 3]
// root-relative (the training mean pose).
RefinerFills MakeRefinerFills(const Skeleton& skeleton, const std::vector<float>& positions,
                              const std::vector<uint8_t>& missing,
                              const std::vector<float>& fallback);

}  // namespace motionfork
