// motionfork info FILE: what a motion file holds.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "motion_options.h"
#include "pipeline/motion_input_json.h"

namespace motionfork::app {
namespace {

struct InfoOptions {
  std::string file;
  MotionInputOptions input;
  std::string json;
};

void RunInfo(const InfoOptions& o, const GlobalOptions& g) {
  const LoadedMotion lm =
      pipeline::LoadMotionInput(o.file, WithConfigDir(o.input, ConfigDir(g.config_dir)));
  const Motion& m = lm.motion;
  const Skeleton& s = m.skeleton();
  const BoundingBox box = ComputeBoundingBox(m);
  if (o.json == "-") {
    EmitJson(o.json, pipeline::MotionInfoJson(o.file, lm, box));
    return;
  }
  std::printf("file:      %s\n", o.file.c_str());
  std::printf("skeleton:  %s (%d joints, root %s)\n", s.name().c_str(), s.num_joints(),
              s.joint_name(0).c_str());
  std::printf("joints:   ");
  for (int j = 0; j < s.num_joints(); ++j) {
    std::printf(" %s", s.joint_name(j).c_str());
    if (!s.is_anonymous() && j > 0) std::printf("<%s", s.joint_name(s.parent(j)).c_str());
  }
  std::printf("\n");
  if (!s.partitions().empty()) {
    for (const Partition& p : s.partitions()) {
      std::printf("parts:     %s:", p.name.c_str());
      for (const BodyPart& part : p.parts)
        std::printf(" %s(%zu)", part.name.c_str(), part.joints.size());
      std::printf("\n");
    }
  }
  std::printf("frames:    %s at %.6g Hz%s (%.2f s)\n", WithThousands(m.num_frames()).c_str(),
              m.fps(), lm.fps_assumed ? " (assumed: the file stores no rate; pass --fps)" : "",
              m.duration_seconds());
  std::printf("bounding box (m): x [%.3f, %.3f]  y [%.3f, %.3f]  z [%.3f, %.3f]\n", box.min[0],
              box.max[0], box.min[1], box.max[1], box.min[2], box.max[2]);
  std::printf("extent (m):       %.3f x %.3f x %.3f\n", box.max[0] - box.min[0],
              box.max[1] - box.min[1], box.max[2] - box.min[2]);
  EmitJson(o.json, pipeline::MotionInfoJson(o.file, lm, box));
}

}  // namespace

void AddInfoCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<InfoOptions>(
      &app, global, RunInfo, "info",
      "Show a motion file's skeleton, frames, frame rate, duration and bounding box");
  AddInputFile(cmd, "FILE", &o->file, "Motion file (.bvh, .npy, .csv)");
  AddMotionInputOptions(cmd, &o->input);
  AddJsonOption(cmd, &o->json, "The report, instead of text on stdout,");
}

}  // namespace motionfork::app
