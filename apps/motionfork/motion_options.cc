#include "motion_options.h"

#include "config/config_paths.h"
#include "io/motion_file.h"

namespace motionfork::app {

void AddMotionInputOptions(CLI::App* cmd, MotionInputOptions* o) {
  cmd->add_option("--skeleton", o->skeleton,
                  "Skeleton config name (bandai, h36m, humaneva) or YAML path: names the joints of "
                  ".npy files and maps files onto that skeleton's protocol joints");
  cmd->add_option("--fps", o->fps,
                  "Frame rate in Hz of files that store none (.npy; .csv without an fps comment); "
                  "default 30")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--bvh-scale", o->bvh_scale,
                  "BVH length unit in metres (0.01 = centimetres, the default; 1 = metres)")
      ->check(CLI::PositiveNumber);
}

std::vector<uint8_t> ConformMask(const Motion& motion, const std::vector<uint8_t>& missing,
                                 const SkeletonConfig& config) {
  // The mask as a motion of 0/1 "positions" goes through the same selection as the motion.
  const Motion as_motion(motion.skeleton_ptr(), motion.fps(),
                         std::vector<float>(missing.begin(), missing.end()));
  const Motion conformed = ConformToSkeleton(as_motion, config);
  std::vector<uint8_t> out(conformed.positions().size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = conformed.positions()[i] != 0.0f;
  return out;
}

LoadedMotion LoadMotionInput(const std::string& path, const MotionInputOptions& o,
                             const std::string& config_dir, std::vector<uint8_t>* missing) {
  LoadedMotion out;
  MotionReadOptions read;
  read.bvh.scale_to_metres = o.bvh_scale;
  read.fps = o.fps > 0 ? o.fps : 30.0;
  if (!o.skeleton.empty()) {
    out.skeleton_config =
        LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", o.skeleton));
  }
  const MotionFormat format = FormatOfPath(path);
  read.missing = missing;
  out.motion = ReadMotionFile(path, read);
  if (format == MotionFormat::kNpy && o.fps <= 0) out.fps_assumed = true;
  if (out.skeleton_config) {
    if (missing) *missing = ConformMask(out.motion, *missing, *out.skeleton_config);
    out.motion = ConformToSkeleton(out.motion, *out.skeleton_config);
  }
  return out;
}

}  // namespace motionfork::app
