// motionfork constraints fit | show: angle-range constraint sets.
#include <cstdio>

#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "io/file_util.h"
#include "pipeline/constraint_fit.h"
#include "pipeline/constraint_fit_text.h"
#include "pipeline/constraint_listing.h"

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

void RunFit(const FitCmd& c, const GlobalOptions& g) {
  RequireArgument(c.out, "-o,--out");
  const std::string& out = c.out;
  pipeline::ConstraintFitRequest o = c.request;
  o.command_line = pipeline::ConstraintFitCommandLine(o, out);
  o.config_dir = ConfigDir(g.config_dir);
  o.cache_dir = CacheDir(g.cache_dir);
  StageBars bars(!g.quiet);
  o.progress = bars.Callback();
  const pipeline::ConstraintFit f = pipeline::FitConstraints(o);
  bars.Finish();
  WriteFileAtomically(out, f.yaml);
  PrintText(pipeline::ConstraintFitText(f));
  std::printf("wrote %s\n", out.c_str());
}

void RunShow(const ShowOptions& o, const GlobalOptions& g) {
  PrintText(pipeline::ConstraintSetListing(ConfigDir(g.config_dir), o.constraints, o.skeleton));
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
a margin, and widened to a constraint's 'anatomical' limit where it has one; written as a
constraint YAML (all-or-nothing) whose header records this command.
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
  fit->add_option("--low", o->request.fit.low_percentile,
                  "Low percentile, percent (default 0: the lowest angle)");
  fit->add_option("--high", o->request.fit.high_percentile,
                  "High percentile, percent (default 100: the highest angle)");
  fit->add_option("--margin", o->request.fit.margin_deg,
                  "Degrees added outside both percentiles (default 5)");
  fit->add_option(
      "--round", o->request.fit.round_deg,
      "Round the bounds outwards to a multiple of this many degrees (default 0.1; 0 = off)");
  fit->add_flag("--leave-one-out", o->request.leave_one_out,
                "Also fit once per training subject (Bandai: style) without its clips and report "
                "the share of its frames the ranges flag");

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
