// Options every subcommand that reads a motion file shares: --skeleton, --fps, --bvh-scale.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "config/skeleton_config.h"
#include "core/motion.h"

namespace motionfork::app {

struct MotionInputOptions {
  std::string skeleton;     // config name or path; "" = as stored in the file
  double fps = 0;           // 0 = from the file, else 30 Hz for files that store none
  double bvh_scale = 0.01;  // BVH length unit -> metres
};

void AddMotionInputOptions(CLI::App* cmd, MotionInputOptions* o);

struct LoadedMotion {
  Motion motion;
  std::optional<SkeletonConfig> skeleton_config;
  bool fps_assumed = false;  // the file stores no frame rate and --fps was not given
};

// Reads the file; with --skeleton, puts it on that skeleton (selection/re-ordering). With
// `missing`, missing values are accepted (NaN in .npy, empty/nan in .csv) and marked there,
// [T, J, 3] on the loaded motion's joints (after --skeleton).
LoadedMotion LoadMotionInput(const std::string& path, const MotionInputOptions& o,
                             const std::string& config_dir,
                             std::vector<uint8_t>* missing = nullptr);

// A missing-value mask [T, J, 3] following a motion through ConformToSkeleton: a value of the
// result is missing when any value it was made from was.
std::vector<uint8_t> ConformMask(const Motion& motion, const std::vector<uint8_t>& missing,
                                 const SkeletonConfig& config);

}  // namespace motionfork::app
