#include "motion_options.h"

#include <cstdio>

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

MotionInputOptions WithConfigDir(MotionInputOptions o, const std::string& config_dir) {
  o.config_dir = config_dir;
  return o;
}

void NoteResampling(const std::string& path, double from_fps, double to_fps) {
  if (from_fps <= 0) return;
  std::fprintf(stderr, "note: resampling %s from %.6g Hz to the model's %.6g Hz\n", path.c_str(),
               from_fps, to_fps);
}

}  // namespace motionfork::app
