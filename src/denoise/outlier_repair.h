// Outliers found and repaired before the denoising refiner (no LibTorch): a joint displaced in a
// frame or two (a marker swapped, a detector's miss) is found by the Hampel test (motion_filters.h)
// on any of its coordinates and filled in again from the frames around it, by linear interpolation
// in time between the joint's nearest frames that passed, not by the window's median (which, on a
// moving joint, is a neighbouring frame's value). The refiner, which smooths what noise is left,
// then reads the repaired motion (refiner_blend.h, DvaeModel::Denoise).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace motionfork {

struct OutlierRepair {
  int half_window = 0;    // frames each side of the Hampel test's window; 0: no repair
  double deviations = 0;  // an outlier is farther than this many scales from the window's median
  // true: the test about the window's robust line instead (the Theil-Sen line: the median of the
  // slopes between its frames), which keeps its power while the joint moves
  bool trend = false;
  bool enabled() const { return half_window > 0; }
};

// "none" or "Hampel test over +-3 frames at 4 deviations".
std::string DescribeOutlierRepair(const OutlierRepair& repair);

// Per frame and joint [T, J] of a motion [T, J, 3], 1 where a coordinate fails the Hampel test.
// Throws std::invalid_argument for a repair that is not enabled or a bad size.
std::vector<uint8_t> OutlierJoints(const std::vector<float>& motion, int joints,
                                   const OutlierRepair& repair);

// The motion with each flagged joint's coordinates interpolated linearly in time between the
// joint's nearest unflagged frames (held at the nearest one before the first or after the last;
// left as they are where every frame of the joint is flagged). `repaired`, if given, receives the
// number of joint-frames repaired. A repair that is not enabled returns the motion unchanged.
std::vector<float> RepairOutliers(const std::vector<float>& motion, int joints,
                                  const OutlierRepair& repair, int* repaired = nullptr);

}  // namespace motionfork
