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
                  "Rig convention (mixamo, cmu, smpl, ...; configs/rigs/) or joint map YAML for "
                  "joints named unlike the model's; default: detected from the names");
  cmd->add_option(
         "--bvh-scale", o->bvh_scale,
         "BVH unit in metres (0.01 = cm); default: read as cm, then as the body's size says")
      ->check(PositiveNumber);
  cmd->add_option("--unit", o->unit, "The file's unit; default: the one giving a human size")
      ->check(CLI::IsMember({"auto", "m", "cm", "mm", "in"}));
  cmd->add_option("--up", o->up, "The file's up axis; default: the pelvis-to-head axis")
      ->check(CLI::IsMember({"auto", "x", "y", "z", "+x", "+y", "+z", "-x", "-y", "-z"},
                            CLI::ignore_case));
  cmd->add_option("--left-right", o->left_right,
                  "Whether the file's left/right labels hold; default: as the knees say")
      ->check(CLI::IsMember({"auto", "as-labelled", "swapped"}));
  cmd->add_flag("--strict", o->strict,
                "Refuse (exit 2) a motion read with a doubt (upside down, sides exchanged, ...)");
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
  PrintInputNotes(path, in.notes);
  NoteResampling(path, in.resampled_from, in.motion.fps());
  return in;
}

void PrintInputNotes(const std::string& path, const std::vector<std::string>& notes) {
  for (const std::string& note : notes)
    std::fprintf(stderr, "%s\n", pipeline::InputNoteLine(path, note).c_str());
}

void NoteResampling(const std::string& path, double from_fps, double to_fps) {
  if (from_fps <= 0) return;
  std::fprintf(stderr, "note: resampling %s from %.6g Hz to the model's %.6g Hz\n", path.c_str(),
               from_fps, to_fps);
}

}  // namespace motionfork::app
