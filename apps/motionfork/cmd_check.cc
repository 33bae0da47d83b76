// motionfork check MOTION: every frame against angle-range constraints.
//
// Exit status: 0 every frame valid (all angles defined and inside their ranges), 1 some frame is
// not, 2 bad input.
#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "io/file_util.h"
#include "motion_options.h"
#include "pipeline/constraint_check.h"
#include "pipeline/constraint_check_json.h"

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

std::string Percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f%%", 100.0 * share);
  return buf;
}

using pipeline::ConstraintCheck;

void PrintText(const CheckOptions& o, const ConstraintCheck& b) {
  const ConstraintSet& set = *b.set;
  const CheckSummary& s = b.summary;
  const CheckResult& r = b.result;
  const Motion& m = b.motion;
  std::printf("motion:       %s (skeleton %s, %d joints, %s frames at %.6g Hz)\n", o.file.c_str(),
              m.skeleton().name().c_str(), m.num_joints(), WithThousands(s.frames).c_str(),
              m.fps());
  std::printf("constraints:  %s (%s), %d angles\n", set.name().c_str(), b.path.c_str(),
              set.num_constraints());
  std::printf("valid frames: %s of %s (%s); %s violate a range, %s have an undefined angle\n\n",
              WithThousands(s.valid_frames).c_str(), WithThousands(s.frames).c_str(),
              Percent(s.valid_frame_share()).c_str(), WithThousands(s.violating_frames).c_str(),
              WithThousands(s.degenerate_frames).c_str());
  size_t width = 10;
  for (const Constraint& c : set.constraints()) width = std::max(width, c.name.size());
  const int w = static_cast<int>(width);
  std::printf("%-*s  %15s  %9s  %8s  %7s  %7s  %9s  %7s  %7s  %s\n", w, "constraint", "range (deg)",
              "violated", "rate", "below", "above", "undefined", "min", "max", "worst frame");
  for (int c = 0; c < set.num_constraints(); ++c) {
    const Constraint& k = set.constraint(c);
    const ConstraintSummary& cs = s.constraints[c];
    char range[48], lo[16], hi[16], worst[48] = "-";
    std::snprintf(range, sizeof(range), "[%5.1f, %5.1f]", k.lower_deg, k.upper_deg);
    const bool any_defined = cs.degenerate < s.frames;
    std::snprintf(lo, sizeof(lo), any_defined ? "%.1f" : "-", cs.min_deg);
    std::snprintf(hi, sizeof(hi), any_defined ? "%.1f" : "-", cs.max_deg);
    if (cs.worst_frame >= 0) {
      std::snprintf(worst, sizeof(worst), "%d (%.1f deg out)", cs.worst_frame, cs.worst_excess_deg);
    }
    std::printf("%-*s  %15s  %9s  %8s  %7s  %7s  %9s  %7s  %7s  %s\n", w, k.name.c_str(), range,
                WithThousands(cs.violations()).c_str(), Percent(cs.violation_rate).c_str(),
                WithThousands(cs.below).c_str(), WithThousands(cs.above).c_str(),
                WithThousands(cs.degenerate).c_str(), lo, hi, worst);
  }
  if (!s.worst_frames.empty()) {
    std::printf("\nworst frames (degrees outside the ranges, summed):\n");
    for (const FrameViolation& fv : s.worst_frames) {
      std::printf("  frame %d (%.2f s), %.1f deg:", fv.frame, fv.frame / m.fps(), fv.excess_deg);
      for (size_t i = 0; i < fv.constraints.size(); ++i) {
        const Constraint& c = set.constraint(fv.constraints[i]);
        const float a = r.angle(fv.frame, fv.constraints[i]);
        std::printf("%s %s %.1f (%s %.1f)", i ? "," : "", c.name.c_str(), a,
                    a < c.lower_deg ? "<" : ">", a < c.lower_deg ? c.lower_deg : c.upper_deg);
      }
      std::printf("\n");
    }
  }
  if (s.degenerate_frames > 0) {
    std::printf(
        "\nundefined angles come from zero-length bones or collinear plane vectors; such "
        "frames do not count as valid\n");
  }
}

void RunCheck(const CheckOptions& o, GlobalOptions& g) {
  const std::string config_dir = ConfigDir(g.config_dir);
  const LoadedMotion lm = pipeline::LoadMotionInput(o.file, WithConfigDir(o.input, config_dir));
  const ConstraintCheck b = pipeline::CheckMotion(lm, o.file, o.constraints, config_dir, o.worst);
  if (!o.angles_csv.empty()) {
    WriteFileAtomically(o.angles_csv, pipeline::AnglesCsv(*b.set, b.result, b.motion.fps()));
  }
  if (o.json != "-") PrintText(o, b);
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
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--angles", o->angles_csv,
                  "Also write every frame's angles (degrees; empty = undefined) to this CSV file");
}

}  // namespace motionfork::app
