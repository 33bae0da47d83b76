// `motionfork info`'s report as text for people: what a motion file holds (motion_input.h). The
// same as JSON: motion_input_json.h.
#pragma once

#include <string>

#include "core/motion.h"
#include "pipeline/motion_input.h"

namespace motionfork::pipeline {

// Skeleton (joints with their parents, body parts), frames, frame rate (and whether it was
// assumed), duration and bounding box in metres; file: as the user named it.
std::string MotionInfoText(const std::string& file, const LoadedMotion& loaded,
                           const BoundingBox& box);

}  // namespace motionfork::pipeline
