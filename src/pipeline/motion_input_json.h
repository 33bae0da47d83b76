// `motionfork info`'s report as JSON: what a motion file holds (motion_input.h).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "core/motion.h"
#include "pipeline/motion_input.h"

namespace motionfork::pipeline {

// Skeleton (joints, parents), frames, frame rate (and whether it was assumed), duration and
// bounding box in metres; file: as the user named it.
nlohmann::ordered_json MotionInfoJson(const std::string& file, const LoadedMotion& loaded,
                                      const BoundingBox& box);

}  // namespace motionfork::pipeline
