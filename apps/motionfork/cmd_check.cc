// motionfork check MOTION: every frame against angle-range constraints.
//
// Exit status: 0 every frame valid (all angles defined and inside their ranges), 1 some frame is
// not, 2 bad input.
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "io/file_util.h"
#include "motion_options.h"
#include "pipeline/constraint_check.h"
#include "pipeline/constraint_check_json.h"
#include "pipeline/constraint_check_text.h"

namespace motionfork::app {
namespace {

constexpr int kExitInvalidFrames = 1;

struct CheckOptions {
  std::string file;
  std::string constraints;  // name or path; "" = from --skeleton or detected from joint names
  MotionInputOptions input;
  std::string json;
  int worst = 5;
  std::string angles_csv;
};

void RunCheck(const CheckOptions& o, GlobalOptions& g) {
  const std::string config_dir = ConfigDir(g.config_dir);
  const LoadedMotion lm = pipeline::LoadMotionInput(o.file, WithConfigDir(o.input, config_dir));
  const pipeline::ConstraintCheck b =
      pipeline::CheckMotion(lm, o.file, o.constraints, config_dir, o.worst);
  if (!o.angles_csv.empty()) {
    WriteFileAtomically(o.angles_csv, pipeline::AnglesCsv(*b.set, b.result, b.motion.fps()));
  }
  PrintInputNotes(o.file, b.notes);
  if (o.json != "-") PrintText(pipeline::ConstraintCheckText(o.file, b));
  EmitJson(o.json, pipeline::ConstraintCheckJson(o.file, b));
  g.exit_code = b.summary.valid_frames == b.summary.frames ? kExitOk : kExitInvalidFrames;
}

}  // namespace

void AddCheckCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<CheckOptions>(
      &app, global, RunCheck, "check",
      R"(Check every frame of a motion against angle-range constraints (configs/constraints/).
Prints the violation rate of each constraint, the worst frames with their angles and the
share of valid frames (every angle defined and inside its range).
Exit status: 0 every frame is valid, 1 some frame is not, 2 bad input or usage.)");
  AddInputFile(cmd, "MOTION", &o->file, "Motion file (.bvh, .npy, .csv)");
  cmd->add_option(
      "--constraints", o->constraints,
      "Constraint set: shipped name (bandai, h36m, humaneva) or YAML path. Default: the "
      "set named like --skeleton, else the one shipped set whose joints the motion has");
  AddMotionInputOptions(cmd, &o->input);
  AddJsonOption(cmd, &o->json,
                "The report (frames, valid_frame_share, per-constraint violation_rate, "
                "worst_frames), instead of text on stdout,");
  cmd->add_option("--worst", o->worst, "How many of the worst frames to list (default 5)")
      ->check(NonNegativeNumber);
  cmd->add_option("--angles", o->angles_csv,
                  "Also write every frame's angles (degrees; empty = undefined) to this CSV file")
      ->check(OutputFile);
}

}  // namespace motionfork::app
