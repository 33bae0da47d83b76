// motionfork synth walk -o FILE: a motion the project makes itself (the demo's built-in history).
#include <cstdio>

#include "app_common.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/skeleton_config.h"
#include "core/demo_motion.h"
#include "flags.h"
#include "io/motion_file.h"

namespace motionfork::app {
namespace {

struct SynthOptions {
  std::string kind = "walk";
  std::string out;
  std::string skeleton = "bandai";
  DemoWalkOptions walk;
};

void RunSynth(const SynthOptions& o, const GlobalOptions& g) {
  const SkeletonConfig sc =
      LoadSkeletonConfig(ResolveConfigPath(ConfigDir(g.config_dir), "skeletons", o.skeleton));
  const Motion m = MakeDemoWalk(sc.skeleton, o.walk);
  WriteMotionFile(o.out, m);
  std::printf(
      "wrote %s: synthetic %s, %d frames at %.6g Hz (%.2f s), %d joints of skeleton '%s', metres, "
      "Y up\n",
      o.out.c_str(), o.kind.c_str(), m.num_frames(), m.fps(), m.num_frames() / m.fps(),
      m.num_joints(), sc.skeleton->name().c_str());
}

}  // namespace

void AddSynthCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<SynthOptions>(
      &app, global, RunSynth, "synth",
      R"(Write a synthetic motion made by a simple gait model (no dataset involved): the demo's
built-in history, and a quick input for trying any command. Hip, knee and arm swing,
the pelvis riding on the lower foot; Bandai protocol skeleton (17 joints), metres, Y up.)");
  cmd->add_option("KIND", o->kind, "Motion to make (walk)")->check(CLI::IsMember({"walk"}));
  AddOutOption(cmd, &o->out, "Output file (.npy, .csv or .bvh); written all-or-nothing");
  cmd->add_option("--frames", o->walk.frames, "Frames (default 60)")->check(PositiveNumber);
  cmd->add_option("--fps", o->walk.fps, "Frame rate, Hz (default 30)")->check(PositiveNumber);
  cmd->add_option("--speed", o->walk.speed, "Walking speed, m/s (default 1.2)");
  cmd->add_option("--stride-hz", o->walk.stride_hz,
                  "Gait cycles (two steps) per second (default 0.9)");
  cmd->add_option("--heading", o->walk.heading_deg,
                  "Walking direction, degrees about +Y from +Z (default 0)");
  cmd->add_option("--skeleton", o->skeleton,
                  "Skeleton config (default bandai; the walk needs its joints)");
}

}  // namespace motionfork::app
