// motionfork constraints fit | show: angle-range constraint sets.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app_common.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "constraints/fit.h"
#include "dataset/dataset.h"
#include "dataset_loading.h"
#include "flags.h"
#include "io/file_util.h"

namespace motionfork::app {
namespace {

struct FitCommandOptions {
  std::string protocol;
  std::string data;
  std::string output;
  std::string constraints;  // definitions; "" = the protocol skeleton's shipped set
  std::string split_file;
  FitOptions fit;
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
std::string FitCommandLine(const FitCommandOptions& o) {
  const FitOptions defaults;
  std::string cmd = "motionfork constraints fit --protocol " + o.protocol + " --data " + o.data +
                    " -o " + o.output;
  if (!o.constraints.empty()) cmd += " --constraints " + o.constraints;
  if (!o.split_file.empty()) cmd += " --split " + o.split_file;
  if (o.fit.low_percentile != defaults.low_percentile)
    cmd += Fmt(" --low %g", o.fit.low_percentile);
  if (o.fit.high_percentile != defaults.high_percentile)
    cmd += Fmt(" --high %g", o.fit.high_percentile);
  if (o.fit.margin_deg != defaults.margin_deg) cmd += Fmt(" --margin %g", o.fit.margin_deg);
  if (o.fit.round_deg != defaults.round_deg) cmd += Fmt(" --round %g", o.fit.round_deg);
  return cmd;
}

// Words of text re-flowed into lines of at most `width` characters.
std::string Wrap(const std::string& text, size_t width = 96) {
  std::string out, line, word;
  auto flush_word = [&] {
    if (word.empty()) return;
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    word.clear();
  };
  for (char c : text) {
    if (c == ' ') {
      flush_word();
    } else {
      word += c;
    }
  }
  flush_word();
  return out + line + "\n";
}

void RunFit(const FitCommandOptions& o, const GlobalOptions& g) {
  Validate(o.fit);
  const std::string config_dir = ConfigDir(g.config_dir);
  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", o.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", protocol.skeleton));
  const std::string definitions = ResolveConfigPath(
      config_dir, "constraints", o.constraints.empty() ? protocol.skeleton : o.constraints);
  ConstraintLoadOptions load_options;
  load_options.require_ranges = false;
  const ConstraintSetSpec spec = LoadConstraintConfig(definitions, load_options);
  ConstraintBuildOptions build_options;
  build_options.require_ranges = false;
  // Bind before the (long) dataset load, so a bad definition fails at once.
  const ConstraintSet set = ConstraintSet::Build(spec, *skeleton.skeleton, build_options);

  const Dataset ds = LoadDatasetWithProgress(protocol, skeleton, o.data, o.split_file, g);
  const std::vector<int> train = ds.ClipIndices(Split::kTrain);
  const std::vector<int> test = ds.ClipIndices(Split::kTest);
  if (train.empty()) {
    throw std::invalid_argument("no training clips in " + o.data + " under protocol '" +
                                protocol.name + "': nothing to fit");
  }
  RangeFitter fitter(set, o.fit);
  {
    ProgressBar bar("measuring angles", !g.quiet);
    for (size_t i = 0; i < train.size(); ++i) {
      fitter.Add(ds.clips[train[i]].motion);
      bar.Update(double(i + 1) / train.size(), ds.clips[train[i]].name);
    }
  }
  const std::vector<FittedRange> ranges = fitter.Fit();
  ConstraintSetSpec fitted = WithFittedRanges(spec, ranges);
  const ConstraintSet fitted_set = ConstraintSet::Build(fitted, *skeleton.skeleton);

  // The held-out split, as a first look at how tight the ranges are.
  long long test_frames = 0, test_invalid = 0;
  std::vector<long long> test_violations(fitted_set.num_constraints(), 0);
  for (int i : test) {
    const CheckResult r = Check(fitted_set, ds.clips[i].motion, o.fit.degeneracy);
    test_frames += r.num_frames;
    for (int t = 0; t < r.num_frames; ++t) {
      bool bad = false;
      for (int c = 0; c < r.num_constraints; ++c) {
        const AngleStatus s = r.at(t, c);
        if (IsViolation(s)) ++test_violations[c];
        bad |= s != AngleStatus::kInside;
      }
      test_invalid += bad;
    }
  }

  const long long train_frames = fitter.frames();
  // Shipped names are shown as the file in the source tree, paths as given.
  const std::string definitions_shown =
      std::filesystem::is_regular_file(o.constraints.empty() ? std::string() : o.constraints)
          ? o.constraints
          : "configs/constraints/" + (o.constraints.empty() ? protocol.skeleton : o.constraints) +
                ".yaml";
  std::string header = "Angle-range constraints for the " + skeleton.skeleton->name() +
                       " skeleton. Ranges FITTED from data by:\n  " + FitCommandLine(o) + "\n";
  std::string about =
      "Definitions: " + definitions_shown + " (re-running the command refits its ranges). Fitted " +
      "on protocol '" + protocol.name + "', train split: " + WithThousands(train.size()) +
      " clips, " + WithThousands(train_frames) + " frames. Each range: percentiles " +
      Fmt("%g", o.fit.low_percentile) + " / " + Fmt("%g", o.fit.high_percentile) +
      " of the angle over those frames (left and right pooled), widened by " +
      Fmt("%g", o.fit.margin_deg) + " degrees" +
      (o.fit.round_deg > 0 ? ", rounded outwards to " + Fmt("%g", o.fit.round_deg) + " degrees"
                           : "") +
      ".";
  if (test_frames > 0) {
    about += " Held-out test split: " + WithThousands(test.size()) + " clips, " +
             WithThousands(test_frames) + " frames, " +
             Fmt("%.3f", 100.0 * test_invalid / test_frames) + "% of them outside some range.";
  }
  header += Wrap(about);
  header += "Format: configs/constraints/README.md.";
  WriteFileAtomically(o.output, FormatConstraintConfig(fitted, header));

  size_t width = 10;
  for (const Constraint& c : fitted_set.constraints()) width = std::max(width, c.name.size());
  const int w = static_cast<int>(width);
  std::printf("fitted %d angles (%zu definitions) on %s train frames of protocol %s\n",
              fitted_set.num_constraints(), spec.constraints.size(),
              WithThousands(train_frames).c_str(), protocol.name.c_str());
  std::printf("%-*s  %12s  %9s  %9s  %16s  %s\n", w, "constraint", "angles", "p_low", "p_high",
              "range (deg)", test_frames ? "test violations" : "");
  for (int c = 0; c < fitted_set.num_constraints(); ++c) {
    const Constraint& k = fitted_set.constraint(c);
    const FittedRange& fr = ranges[k.spec_index];
    std::printf("%-*s  %12s  %9.2f  %9.2f  [%6.1f, %6.1f]", w, k.name.c_str(),
                WithThousands(fr.samples).c_str(), fr.low_value_deg, fr.high_value_deg, k.lower_deg,
                k.upper_deg);
    if (test_frames) std::printf("  %.3f%%", 100.0 * test_violations[c] / test_frames);
    std::printf("\n");
  }
  if (test_frames) {
    std::printf("test split: %s frames, %.3f%% outside some range or undefined\n",
                WithThousands(test_frames).c_str(), 100.0 * test_invalid / test_frames);
  }
  std::printf("wrote %s\n", o.output.c_str());
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

  auto f = std::make_shared<FitCommandOptions>();
  CLI::App* fit = cmd->add_subcommand(
      "fit",
      "Fit every constraint's range from the training split of a protocol's data: a low and a\n"
      "high percentile of the angle over all training frames (left and right pooled), widened by\n"
      "a margin, written as a constraint YAML (all-or-nothing) whose header records this command.\n"
      "The definitions come from --constraints (default: the set named like the protocol's\n"
      "skeleton); their ranges, if any, are replaced.");
  fit->add_option("--protocol", f->protocol, "Protocol name (bandai, h36m, humaneva) or YAML path")
      ->required();
  fit->add_option("--data", f->data, "Data folder of the protocol (as for 'dataset stats')")
      ->required()
      ->check(CLI::ExistingDirectory);
  fit->add_option("-o,--out", f->output, "Constraint YAML to write (required)");
  AddDeprecatedOption(fit, "--output", "-o/--out", &f->output);
  fit->add_option("--constraints", f->constraints,
                  "Definitions: shipped name or YAML path (ranges optional)");
  fit->add_option("--split", f->split_file, "Split file overriding the protocol's split.file");
  fit->add_option("--low", f->fit.low_percentile, "Low percentile, percent (default 0.1)");
  fit->add_option("--high", f->fit.high_percentile, "High percentile, percent (default 99.9)");
  fit->add_option("--margin", f->fit.margin_deg,
                  "Degrees added outside both percentiles (default 2)");
  fit->add_option(
      "--round", f->fit.round_deg,
      "Round the bounds outwards to a multiple of this many degrees (default 0.1; 0 = off)");
  fit->callback([f, &global] {
    RequireArgument(f->output, "-o,--out");
    RunFit(*f, global);
  });

  auto s = std::make_shared<ShowOptions>();
  CLI::App* show = cmd->add_subcommand(
      "show",
      "List a constraint set's angles as bound to a skeleton: per-side instances expanded,\n"
      "joint names resolved, ranges");
  show->add_option("CONSTRAINTS", s->constraints,
                   "Shipped name (bandai, h36m, humaneva) or YAML path")
      ->required();
  show->add_option("--skeleton", s->skeleton,
                   "Skeleton config (default: the set's own 'skeleton')");
  show->callback([s, &global] { RunShow(*s, global); });
}

}  // namespace motionfork::app
