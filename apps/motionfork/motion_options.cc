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

LoadedMotion LoadMotionInput(const std::string& path, const MotionInputOptions& o,
                             const std::string& config_dir) {
  LoadedMotion out;
  MotionReadOptions read;
  read.bvh.scale_to_metres = o.bvh_scale;
  read.fps = o.fps > 0 ? o.fps : 30.0;
  if (!o.skeleton.empty()) {
    out.skeleton_config = LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", o.skeleton));
  }
  const MotionFormat format = FormatOfPath(path);
  out.motion = ReadMotionFile(path, read);
  if (format == MotionFormat::kNpy && o.fps <= 0) out.fps_assumed = true;
  if (out.skeleton_config) out.motion = ConformToSkeleton(out.motion, *out.skeleton_config);
  return out;
}

}  // namespace motionfork::app
