// Frame-rate conversion by linear interpolation in time.
#pragma once

#include <vector>

#include "core/motion.h"

namespace motionfork {

// Resamples to target_fps (Hz). New frame i sits at time i / target_fps seconds; its positions are
// linearly interpolated between the two nearest source frames. Frames run while that time stays
// within the source clip, so an integer ratio (120 -> 30 Hz, 50 -> 25 Hz) keeps exactly every
// k-th source frame. Throws std::invalid_argument for target_fps <= 0.
Motion Resample(const Motion& motion, double target_fps);

// Positions [T, J, 3] played `factor` times slower at the same frame rate: new frame i at source
// time i / factor, linearly interpolated (speeds / factor, accelerations / factor^2; how a slower
// performer might move). Throws std::invalid_argument for factor <= 0 or a bad size.
std::vector<float> SlowDown(const std::vector<float>& positions, int joints, double factor);

}  // namespace motionfork
