// A motion file with missing values, put on an HG-VAE's skeleton and frame rate (impute, ood,
// predict --impute).
#pragma once

#include <string>
#include <vector>

#include "core/motion.h"
#include "core/skeleton.h"
#include "motion_options.h"

namespace motionfork::app {

struct MotionWithGaps {
  Motion motion;                 // missing values hold 0
  std::vector<uint8_t> missing;  // [T, J, 3], 1 = missing
};

// Reads `path` (missing values allowed), maps it onto `skeleton` by joint names (or --skeleton's
// selection) and resamples to fps; masks from --mask specs are added (seed for random ones).
MotionWithGaps LoadMotionWithGaps(const std::string& path, const MotionInputOptions& input,
                                  const std::string& config_dir,
                                  const std::shared_ptr<const Skeleton>& skeleton, double fps,
                                  const std::vector<std::string>& mask_specs, uint64_t seed);

}  // namespace motionfork::app
