// Frame-rate conversion by linear interpolation in time.
#pragma once

#include "core/motion.h"

namespace motionfork {

// Resamples to target_fps (Hz). New frame i sits at time i / target_fps seconds; its positions are
// linearly interpolated between the two nearest source frames. Frames run while that time stays
// within the source clip, so an integer ratio (120 -> 30 Hz, 50 -> 25 Hz) keeps exactly every
// k-th source frame. Throws std::invalid_argument for target_fps <= 0.
Motion Resample(const Motion& motion, double target_fps);

}  // namespace motionfork
