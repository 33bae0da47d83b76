// motionfork check MOTION: every frame against angle-range constraints.
//
// Exit status: 0 every frame valid (all angles defined and inside their ranges), 1 some frame is
// not, 2 bad input.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "app_common.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "core/error.h"
#include "io/file_util.h"
#include "motion_options.h"

namespace motionfork::app {
namespace {

constexpr int kExitInvalidFrames = 1;

struct CheckOptions {
  std::string file;
  std::string constraints;  // name or path; "" = from --skeleton or detected from joint names
  MotionInputOptions input;
  bool json = false;
  int worst = 5;
  std::string angles_csv;
};

std::string Json(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

std::string Percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f%%", 100.0 * share);
  return buf;
}

// A constraint set bound to the motion, with the motion as the set sees it.
struct Bound {
  std::string path;
  ConstraintSetSpec spec;
  Motion motion;
  std::optional<ConstraintSet> set;
};

// Puts the motion on the set's own skeleton config when it names one and the motion fits it
// (a 22-joint Bandai BVH -> the 17 protocol joints; a 17-joint .npy -> named joints); otherwise
// the set binds to the motion's joint names as they are.
Bound BindSet(const std::string& path, const Motion& motion, bool skeleton_given,
              const std::string& config_dir) {
  Bound b;
  b.path = path;
  b.spec = LoadConstraintConfig(path);
  b.motion = motion;
  if (!skeleton_given && !b.spec.skeleton.empty()) {
    try {
      const SkeletonConfig sc =
          LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", b.spec.skeleton));
      b.motion = ConformToSkeleton(motion, sc);
    } catch (const std::invalid_argument&) {
      // Not that skeleton's joints: bind by the motion's own names below.
    }
  }
  if (b.motion.skeleton().is_anonymous() && b.motion.skeleton().joint_name(0) == "j0") {
    throw std::invalid_argument(
        "the motion's joints have no names (a .npy file) and do not fit "
        "skeleton '" +
        b.spec.skeleton + "' of constraint set '" + b.spec.name + "': pass --skeleton NAME");
  }
  b.set = ConstraintSet::Build(b.spec, b.motion.skeleton());
  return b;
}

Bound ChooseSet(const CheckOptions& o, const LoadedMotion& lm, const std::string& config_dir) {
  const Motion& motion = lm.motion;
  const bool skeleton_given = lm.skeleton_config.has_value();
  if (!o.constraints.empty()) {
    return BindSet(ResolveConfigPath(config_dir, "constraints", o.constraints), motion,
                   skeleton_given, config_dir);
  }
  if (skeleton_given) {
    // The shipped set named like the skeleton (bandai, h36m, humaneva), if there is one.
    const std::filesystem::path shipped = std::filesystem::path(config_dir) / "constraints" /
                                          (lm.skeleton_config->skeleton->name() + ".yaml");
    if (std::filesystem::is_regular_file(shipped)) {
      return BindSet(shipped.string(), motion, skeleton_given, config_dir);
    }
  }
  // Detect: the shipped sets whose joints the motion has.
  std::vector<Bound> fits;
  std::string names;
  for (const std::string& name : ListConfigs(config_dir, "constraints")) {
    names += (names.empty() ? "" : ", ") + name;
    try {
      fits.push_back(BindSet(ResolveConfigPath(config_dir, "constraints", name), motion,
                             skeleton_given, config_dir));
    } catch (const std::exception&) {
      // Does not fit this motion.
    }
  }
  if (fits.size() == 1) return std::move(fits.front());
  std::string which;
  for (const Bound& b : fits) which += (which.empty() ? "" : ", ") + b.spec.name;
  throw std::invalid_argument(
      fits.empty() ? "no shipped constraint set (" + names + ") fits the joints of " + o.file +
                         " (skeleton '" + motion.skeleton().name() +
                         "'): pass --constraints NAME|FILE, or --skeleton NAME"
                   : "several shipped constraint sets fit " + o.file + " (" + which +
                         "): choose one with --constraints NAME or --skeleton NAME");
}

void WriteAnglesCsv(const std::string& path, const ConstraintSet& set, const CheckResult& r,
                    double fps) {
  std::string out = "frame,time_s";
  for (const Constraint& c : set.constraints()) out += "," + c.name;
  out += "\n";
  char buf[32];
  for (int t = 0; t < r.num_frames; ++t) {
    std::snprintf(buf, sizeof(buf), "%d,%.6g", t, t / fps);
    out += buf;
    for (int c = 0; c < r.num_constraints; ++c) {
      out += ',';
      if (r.at(t, c) != AngleStatus::kDegenerate) {
        std::snprintf(buf, sizeof(buf), "%.4f", r.angle(t, c));
        out += buf;
      }
    }
    out += '\n';
  }
  WriteFileAtomically(path, out);
}

void PrintJson(const CheckOptions& o, const Bound& b, const CheckResult& r, const CheckSummary& s) {
  const ConstraintSet& set = *b.set;
  const double fps = b.motion.fps();
  std::string j =
      "{\"file\": " + Json(o.file) + ", \"skeleton\": " + Json(b.motion.skeleton().name()) +
      ", \"constraint_set\": " + Json(set.name()) + ", \"constraints_file\": " + Json(b.path) +
      ", \"fps\": " + Num(fps) + ", \"frames\": " + std::to_string(s.frames) +
      ", \"valid_frames\": " + std::to_string(s.valid_frames) +
      ", \"valid_frame_share\": " + Num(s.valid_frame_share()) +
      ", \"violating_frames\": " + std::to_string(s.violating_frames) +
      ", \"violating_frame_share\": " + Num(s.frames ? double(s.violating_frames) / s.frames : 0) +
      ", \"degenerate_frames\": " + std::to_string(s.degenerate_frames) + ", \"constraints\": [";
  for (int c = 0; c < set.num_constraints(); ++c) {
    const Constraint& k = set.constraint(c);
    const ConstraintSummary& cs = s.constraints[c];
    const bool any_defined = cs.degenerate < s.frames;
    j += std::string(c ? ", " : "") + "{\"name\": " + Json(k.name) +
         ", \"side\": " + Json(ToString(k.side)) + ", \"a\": " + Json(k.a_text) +
         ", \"b\": " + Json(k.b_text) + ", \"lower_deg\": " + Num(k.lower_deg) +
         ", \"upper_deg\": " + Num(k.upper_deg) +
         ", \"violations\": " + std::to_string(cs.violations()) +
         ", \"violation_rate\": " + Num(cs.violation_rate) +
         ", \"below\": " + std::to_string(cs.below) + ", \"above\": " + std::to_string(cs.above) +
         ", \"degenerate\": " + std::to_string(cs.degenerate) +
         ", \"min_deg\": " + (any_defined ? Num(cs.min_deg) : "null") +
         ", \"max_deg\": " + (any_defined ? Num(cs.max_deg) : "null") +
         ", \"worst_frame\": " + (cs.worst_frame >= 0 ? std::to_string(cs.worst_frame) : "null") +
         ", \"worst_excess_deg\": " + Num(cs.worst_excess_deg) + "}";
  }
  j += "], \"worst_frames\": [";
  for (size_t k = 0; k < s.worst_frames.size(); ++k) {
    const FrameViolation& fv = s.worst_frames[k];
    j += std::string(k ? ", " : "") + "{\"frame\": " + std::to_string(fv.frame) +
         ", \"time_s\": " + Num(fv.frame / fps) + ", \"excess_deg\": " + Num(fv.excess_deg) +
         ", \"violations\": [";
    for (size_t i = 0; i < fv.constraints.size(); ++i) {
      const Constraint& c = set.constraint(fv.constraints[i]);
      j += std::string(i ? ", " : "") + "{\"constraint\": " + Json(c.name) +
           ", \"angle_deg\": " + Num(r.angle(fv.frame, fv.constraints[i])) +
           ", \"lower_deg\": " + Num(c.lower_deg) + ", \"upper_deg\": " + Num(c.upper_deg) + "}";
    }
    j += "]}";
  }
  j += "]}\n";
  std::fputs(j.c_str(), stdout);
}

void PrintText(const CheckOptions& o, const Bound& b, const CheckResult& r, const CheckSummary& s) {
  const ConstraintSet& set = *b.set;
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
  const Bound b = ChooseSet(o, lm, config_dir);
  const CheckResult r = Check(*b.set, b.motion);
  const CheckSummary s = Summarize(*b.set, r, o.worst);
  if (!o.angles_csv.empty()) WriteAnglesCsv(o.angles_csv, *b.set, r, b.motion.fps());
  if (o.json) {
    PrintJson(o, b, r, s);
  } else {
    PrintText(o, b, r, s);
  }
  g.exit_code = s.valid_frames == s.frames ? kExitOk : kExitInvalidFrames;
}

}  // namespace

void AddCheckCommand(CLI::App& app, GlobalOptions& global) {
  auto o = std::make_shared<CheckOptions>();
  CLI::App* cmd = app.add_subcommand(
      "check",
      "Check every frame of a motion against angle-range constraints (configs/constraints/).\n"
      "Prints the violation rate of each constraint, the worst frames with their angles and the\n"
      "share of valid frames (every angle defined and inside its range).\n"
      "Exit status: 0 every frame is valid, 1 some frame is not, 2 bad input or usage.");
  cmd->add_option("MOTION", o->file, "Motion file (.bvh, .npy, .csv)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option(
      "--constraints", o->constraints,
      "Constraint set: shipped name (bandai, h36m, humaneva) or YAML path. Default: the "
      "set named like --skeleton, else the one shipped set whose joints the motion has");
  AddMotionInputOptions(cmd, &o->input);
  cmd->add_flag("--json", o->json,
                "Print one JSON object (frames, valid_frame_share, per-constraint violation_rate, "
                "worst_frames) instead of text");
  cmd->add_option("--worst", o->worst, "How many of the worst frames to list (default 5)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--angles", o->angles_csv,
                  "Also write every frame's angles (degrees; empty = undefined) to this CSV file");
  cmd->callback([o, &global] { RunCheck(*o, global); });
}

}  // namespace motionfork::app
