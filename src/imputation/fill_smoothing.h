// The imputation's last stage: the filled values pulled towards a smooth path in time. Per
// coordinate, the missing values x minimise
//   sum over missing values of (x - filled)^2 / lambda  +  sum over frames of (second difference)^2
// with the observed values held where they are: a value trusted less (larger lambda) follows the
// acceleration-free path through its neighbours more. Where a gap is bracketed by observed frames
// this smooths the jitter a fill can leave between them; where it is observed on one side only (the
// last frames of a history) it lets the values go on with the motion's velocity instead of
// stopping. Values never observed in their coordinate are left as filled.
#pragma once

#include <cstdint>
#include <vector>

namespace motionfork {

struct FillSmoothing {
  double bracketed = 0;  // lambda of values with an observed frame before and after (0: kept)
  double one_sided = 0;  // lambda of values observed on one side only (0: kept)
  bool active() const { return bracketed > 0 || one_sided > 0; }
};

// values, mask: [T, N] frame-major (1 = missing, filled in values). Returns the smoothed values
// (observed ones unchanged). Throws std::invalid_argument on a size mismatch or a negative or
// non-finite lambda.
std::vector<float> SmoothFilledValues(const std::vector<float>& values,
                                      const std::vector<uint8_t>& mask, int coords,
                                      const FillSmoothing& smoothing);

}  // namespace motionfork
