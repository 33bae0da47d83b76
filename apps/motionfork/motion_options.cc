#include "motion_options.h"

#include <cstdio>
#include <memory>

#include "app_common.h"
#include "flags.h"

namespace motionfork::app {

void AddMotionInputOptions(CLI::App* cmd, MotionInputOptions* o) {
  cmd->add_option("--skeleton", o->skeleton,
                  "Skeleton config name (bandai, h36m, humaneva) or YAML path: names the joints of "
                  ".npy files and maps files onto that skeleton's protocol joints");
  cmd->add_option("--fps", o->fps,
                  "Frame rate in Hz of files that store none (.npy; .csv without an fps comment); "
                  "default 30")
      ->check(PositiveNumber);
  cmd->add_option("--joint-map", o->joint_map,
                  "How a file's joints map onto the model's when their names differ: a rig "
                  "convention (bandai, mixamo, cmu, unreal, unreal5, smpl, h36m, humaneva) or a "
                  "joint map YAML (configs/rigs/README.md); default: the convention that explains "
                  "the file's joint names");
  cmd->add_option("--bvh-scale", o->bvh_scale,
                  "BVH length unit in metres (0.01 = centimetres; 1 = metres); default: read as "
                  "centimetres, and on the way onto a model the unit the body's size says")
      ->check(PositiveNumber);
  cmd->add_option("--unit", o->unit,
                  "Length unit of the file's values (m, cm, mm, in); default: the one that gives "
                  "the body a human size")
      ->check(CLI::IsMember({"auto", "m", "cm", "mm", "in"}));
  cmd->add_option("--up", o->up,
                  "The file's up axis (y, z, x, -y, -z, -x); default: the axis along which the "
                  "head is above the pelvis (Bandai/BVH: y; Human3.6M exports: z)")
      ->check(CLI::IsMember({"auto", "x", "y", "z", "+x", "+y", "+z", "-x", "-y", "-z"},
                            CLI::ignore_case));
  cmd->add_flag("--strict", o->strict,
                "Refuse (exit 2) a motion that reads with a doubt (upside down, left/right labels "
                "exchanged, no human size in any unit) instead of warning and going on");
  cmd->add_option("--left-right", o->left_right,
                  "as-labelled or swapped: whether the file's left/right joint labels are right; "
                  "default: as the body says (knees bend forward)")
      ->check(CLI::IsMember({"auto", "as-labelled", "swapped"}));
}

MotionInputOptions WithConfigDir(MotionInputOptions o, const std::string& config_dir) {
  o.config_dir = config_dir;
  return o;
}

MotionWithGaps LoadMotionForModel(const std::string& path, const MotionInputOptions& input,
                                  const GlobalOptions& global, const Skeleton& skeleton, double fps,
                                  const std::string& protocol,
                                  const std::vector<std::string>& masks, uint64_t seed) {
  MotionInputOptions how = WithConfigDir(input, ConfigDir(global.config_dir));
  how.target_up = pipeline::ProtocolUp(how.config_dir, protocol);
  MotionWithGaps in = pipeline::LoadMotionWithGaps(
      path, how, std::make_shared<const Skeleton>(skeleton), fps, masks, seed);
  for (const std::string& note : in.notes)
    std::fprintf(stderr, "%s\n", pipeline::InputNoteLine(path, note).c_str());
  NoteResampling(path, in.resampled_from, in.motion.fps());
  return in;
}

void NoteResampling(const std::string& path, double from_fps, double to_fps) {
  if (from_fps <= 0) return;
  std::fprintf(stderr, "note: resampling %s from %.6g Hz to the model's %.6g Hz\n", path.c_str(),
               from_fps, to_fps);
}

}  // namespace motionfork::app
