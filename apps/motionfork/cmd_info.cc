// motionfork info FILE: what a motion file holds.
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "motion_options.h"
#include "pipeline/motion_input_json.h"
#include "pipeline/motion_input_text.h"

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
  const BoundingBox box = ComputeBoundingBox(lm.motion);
  if (o.json == "-") {
    EmitJson(o.json, pipeline::MotionInfoJson(o.file, lm, box));
    return;
  }
  PrintText(pipeline::MotionInfoText(o.file, lm, box));
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
