// What `motionfork denoise` says of a motion it denoised, as text for people.
#pragma once

#include <string>

#include "core/motion.h"
#include "denoise/dvae_model.h"

namespace motionfork {

// Frames, windows, mode and speed, and how far the joints moved (input -> output).
std::string DenoisedMotionText(const DvaeModel& model, const DenoiseOptions& options,
                               const DenoiseStats& stats, const Motion& input,
                               const Motion& output);
// The noise model's typical standard deviation per joint, in cm (one line).
std::string NoiseModelText(const DvaeModel& model, const DenoiseStats& stats);

}  // namespace motionfork
