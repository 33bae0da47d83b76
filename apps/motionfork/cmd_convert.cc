// motionfork convert IN OUT: between motion formats, optionally onto a protocol skeleton.
#include <cstdio>

#include "app_common.h"
#include "commands.h"
#include "core/resample.h"
#include "flags.h"
#include "io/motion_file.h"
#include "motion_options.h"

namespace motionfork::app {
namespace {

struct ConvertOptions {
  std::string in, out;
  MotionInputOptions input;
  double target_fps = 0;
  bool root_relative = false;
};

void RunConvert(const ConvertOptions& o, const GlobalOptions& g) {
  FormatOfPath(o.out);  // fail on an unknown output extension before any reading
  LoadedMotion lm =
      pipeline::LoadMotionInput(o.in, WithConfigDir(o.input, ConfigDir(g.config_dir)));
  Motion m = std::move(lm.motion);
  if (o.target_fps > 0) m = Resample(m, o.target_fps);
  if (o.root_relative) m = RootRelative(m);
  WriteMotionFile(o.out, m);
  std::printf("wrote %s: %s, %d joints, %s frames at %.6g Hz\n", o.out.c_str(),
              m.skeleton().name().c_str(), m.num_joints(), WithThousands(m.num_frames()).c_str(),
              m.fps());
}

}  // namespace

void AddConvertCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<ConvertOptions>(
      &app, global, RunConvert, "convert",
      R"(Convert a motion file between .bvh, .npy [T, J, 3] and .csv (metres). Writing .bvh fits joint
rotations to the positions (needs a skeleton with parents, e.g. --skeleton bandai).
With --skeleton, the motion is mapped onto that skeleton's protocol joints (e.g. a 22-joint
Bandai BVH to the 17 joints of the Bandai protocol). VideoPose3D .npz files are converted
with tools/videopose3d_to_motionfork.py.)");
  AddInputFile(cmd, "IN", &o->in, "Input motion file");
  cmd->add_option("OUT,-o,--out", o->out,
                  "Output file (.bvh, .npy or .csv), as the second argument or -o/--out (as the "
                  "other commands take it); written all-or-nothing")
      ->required()
      ->check(OutputFile);
  AddMotionInputOptions(cmd, &o->input);
  cmd->add_option("--resample", o->target_fps,
                  "Resample to this frame rate, Hz (linear interpolation)")
      ->check(PositiveNumber);
  cmd->add_flag("--root-relative", o->root_relative,
                "Subtract the root joint's position in every frame");
}

}  // namespace motionfork::app
