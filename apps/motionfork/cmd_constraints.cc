// motionfork constraints fit | show: angle-range constraint sets.
#include <algorithm>
#include <cstdio>

#include "app_common.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "constraints/constraint_set.h"
#include "flags.h"
#include "io/file_util.h"
#include "pipeline/constraint_fit.h"

namespace motionfork::app {
namespace {

struct FitCmd {
  pipeline::ConstraintFitRequest request;
  std::string out;
};

struct ShowOptions {
  std::string constraints;
  std::string skeleton;
};

std::string Fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

// The command line that reproduces a fit, for the written file's header.
std::string FitCommandLine(const pipeline::ConstraintFitRequest& o, const std::string& out) {
  const FitOptions defaults;
  std::string cmd =
      "motionfork constraints fit --protocol " + o.protocol + " --data " + o.data + " -o " + out;
  if (!o.constraints.empty()) cmd += " --constraints " + o.constraints;
  if (!o.split_file.empty()) cmd += " --split " + o.split_file;
  if (o.fit.low_percentile != defaults.low_percentile)
    cmd += Fmt(" --low %g", o.fit.low_percentile);
  if (o.fit.high_percentile != defaults.high_percentile) {
    cmd += Fmt(" --high %g", o.fit.high_percentile);
  }
  if (o.fit.margin_deg != defaults.margin_deg) cmd += Fmt(" --margin %g", o.fit.margin_deg);
  if (o.fit.round_deg != defaults.round_deg) cmd += Fmt(" --round %g", o.fit.round_deg);
  return cmd;
}

void RunFit(const FitCmd& c, const GlobalOptions& g) {
  RequireArgument(c.out, "-o,--out");
  const std::string& out = c.out;
  pipeline::ConstraintFitRequest o = c.request;
  o.command_line = FitCommandLine(o, out);
  o.config_dir = ConfigDir(g.config_dir);
  o.cache_dir = CacheDir(g.cache_dir);
  StageBars bars(!g.quiet);
  o.progress = bars.Callback();
  const pipeline::ConstraintFit f = pipeline::FitConstraints(o);
  bars.Finish();
  WriteFileAtomically(out, f.yaml);
  const ConstraintSet& set = *f.fitted;
  size_t width = 10;
  for (const Constraint& c : set.constraints()) width = std::max(width, c.name.size());
  const int w = static_cast<int>(width);
  std::printf("fitted %d angles (%zu definitions) on %s train frames of protocol %s\n",
              set.num_constraints(), f.definitions.constraints.size(),
              WithThousands(f.train_frames).c_str(), f.protocol.name.c_str());
  std::printf("%-*s  %12s  %9s  %9s  %16s  %s\n", w, "constraint", "angles", "p_low", "p_high",
              "range (deg)", f.test_frames ? "test violations" : "");
  for (int c = 0; c < set.num_constraints(); ++c) {
    const Constraint& k = set.constraint(c);
    const FittedRange& fr = f.ranges[k.spec_index];
    std::printf("%-*s  %12s  %9.2f  %9.2f  [%6.1f, %6.1f]", w, k.name.c_str(),
                WithThousands(fr.samples).c_str(), fr.low_value_deg, fr.high_value_deg, k.lower_deg,
                k.upper_deg);
    if (f.test_frames) std::printf("  %.3f%%", 100.0 * f.test_violations[c] / f.test_frames);
    std::printf("\n");
  }
  if (f.test_frames) {
    std::printf("test split: %s frames, %.3f%% outside some range or undefined\n",
                WithThousands(f.test_frames).c_str(), 100.0 * f.test_invalid / f.test_frames);
  }
  std::printf("wrote %s\n", out.c_str());
}

void RunShow(const ShowOptions& o, const GlobalOptions& g) {
  const std::string config_dir = ConfigDir(g.config_dir);
  const std::string path = ResolveConfigPath(config_dir, "constraints", o.constraints);
  ConstraintLoadOptions load_options;
  load_options.require_ranges = false;
  const ConstraintSetSpec spec = LoadConstraintConfig(path, load_options);
  const std::string skeleton_name = o.skeleton.empty() ? spec.skeleton : o.skeleton;
  if (skeleton_name.empty()) {
    throw std::invalid_argument(path + " names no skeleton: pass --skeleton NAME");
  }
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", skeleton_name));
  ConstraintBuildOptions build_options;
  build_options.require_ranges = false;
  const ConstraintSet set = ConstraintSet::Build(spec, *skeleton.skeleton, build_options);
  std::printf(
      "constraint set %s (%s) on skeleton %s: %d angles from %zu definitions, %d vector "
      "operations\n",
      set.name().c_str(), path.c_str(), skeleton.skeleton->name().c_str(), set.num_constraints(),
      spec.constraints.size(), set.num_registers());
  for (const Constraint& c : set.constraints()) {
    if (c.has_range) {
      std::printf("\n%s  [%g, %g] deg\n", c.name.c_str(), c.lower_deg, c.upper_deg);
    } else {
      std::printf("\n%s  (no range yet)\n", c.name.c_str());
    }
    std::printf("  a = %s\n  b = %s\n", c.a_text.c_str(), c.b_text.c_str());
  }
}

}  // namespace

void AddConstraintsCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* cmd =
      app.add_subcommand("constraints", "Angle-range constraint sets (configs/constraints/)");
  cmd->require_subcommand(1);

  const auto [fit, o] = AddSubcommand<FitCmd>(
      cmd, global, RunFit, "fit",
      R"(Fit every constraint's range from the training split of a protocol's data: a low and a
high percentile of the angle over all training frames (left and right pooled), widened by
a margin, written as a constraint YAML (all-or-nothing) whose header records this command.
The definitions come from --constraints (default: the set named like the protocol's
skeleton); their ranges, if any, are replaced.)");
  fit->add_option("--protocol", o->request.protocol,
                  "Protocol name (bandai, h36m, humaneva) or YAML path")
      ->required();
  AddDataOption(fit, &o->request.data, "Data folder of the protocol (as for 'dataset stats')");
  fit->add_option("-o,--out", o->out, "Constraint YAML to write (required)");
  AddDeprecatedOption(fit, "--output", "-o/--out", &o->out);
  fit->add_option("--constraints", o->request.constraints,
                  "Definitions: shipped name or YAML path (ranges optional)");
  fit->add_option("--split", o->request.split_file,
                  "Split file overriding the protocol's split.file");
  fit->add_option("--low", o->request.fit.low_percentile, "Low percentile, percent (default 0.1)");
  fit->add_option("--high", o->request.fit.high_percentile,
                  "High percentile, percent (default 99.9)");
  fit->add_option("--margin", o->request.fit.margin_deg,
                  "Degrees added outside both percentiles (default 2)");
  fit->add_option(
      "--round", o->request.fit.round_deg,
      "Round the bounds outwards to a multiple of this many degrees (default 0.1; 0 = off)");

  const auto [show, s] = AddSubcommand<ShowOptions>(
      cmd, global, RunShow, "show",
      R"(List a constraint set's angles as bound to a skeleton: per-side instances expanded,
joint names resolved, ranges)");
  show->add_option("CONSTRAINTS", s->constraints,
                   "Shipped name (bandai, h36m, humaneva) or YAML path")
      ->required();
  show->add_option("--skeleton", s->skeleton,
                   "Skeleton config (default: the set's own 'skeleton')");
}

}  // namespace motionfork::app
