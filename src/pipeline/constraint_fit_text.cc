#include "pipeline/constraint_fit_text.h"

#include <algorithm>

#include "core/text_format.h"

namespace motionfork::pipeline {
namespace {

// One row per left-out subject: its frames against ranges fitted without it, and the constraint
// that flags most of them.
void AppendLeftOut(std::string* text, const ConstraintFit& f) {
  const ConstraintSet& set = *f.fitted;
  size_t width = 12;
  for (const LeftOutSubject& l : f.left_out) width = std::max(width, l.subject.size());
  const int w = static_cast<int>(width);
  StringAppendf(text,
                "\nleave one subject out (ranges fitted on the other training subjects, checked on "
                "the left-out one's frames):\n%-*s  %5s  %9s  %9s  %s\n",
                w, "left out", "clips", "frames", "flagged", "most flagged by");
  long long frames = 0, flagged = 0;
  for (const LeftOutSubject& l : f.left_out) {
    const FrameCheck& c = l.check;
    const auto most = std::max_element(c.violations.begin(), c.violations.end());
    std::string by = "-";
    if (most != c.violations.end() && *most > 0) {
      by = StringPrintf("%s (%.3f%%)",
                        set.constraint(static_cast<int>(most - c.violations.begin())).name.c_str(),
                        100.0 * *most / c.frames);
    }
    const double share = c.frames ? 100.0 * c.flagged / c.frames : 0.0;
    StringAppendf(text, "%-*s  %5lld  %9s  %8.3f%%  %s\n", w,
                  l.subject.empty() ? "(none)" : l.subject.c_str(), l.clips,
                  WithThousands(c.frames).c_str(), share, by.c_str());
    frames += c.frames;
    flagged += c.flagged;
  }
  double worst = 0;
  MostFlaggedLeftOut(f, &worst);
  StringAppendf(text, "%-*s  %5s  %9s  %8.3f%%  worst subject %.3f%%\n", w, "all", "",
                WithThousands(frames).c_str(), frames ? 100.0 * flagged / frames : 0.0, worst);
}

}  // namespace

std::string ConstraintFitText(const ConstraintFit& f) {
  std::string text;
  const ConstraintSet& set = *f.fitted;
  size_t width = 10;
  for (const Constraint& c : set.constraints()) width = std::max(width, c.name.size());
  const int w = static_cast<int>(width);
  StringAppendf(&text, "fitted %d angles (%zu definitions) on %s train frames of protocol %s\n",
                set.num_constraints(), f.definitions.constraints.size(),
                WithThousands(f.train_frames).c_str(), f.protocol.name.c_str());
  StringAppendf(&text, "%-*s  %12s  %9s  %9s  %16s  %s\n", w, "constraint", "angles", "p_low",
                "p_high", "range (deg)", f.test.frames ? "test violations" : "");
  for (int c = 0; c < set.num_constraints(); ++c) {
    const Constraint& k = set.constraint(c);
    const FittedRange& fr = f.ranges[k.spec_index];
    StringAppendf(&text, "%-*s  %12s  %9.2f  %9.2f  [%6.1f, %6.1f]", w, k.name.c_str(),
                  WithThousands(fr.samples).c_str(), fr.low_value_deg, fr.high_value_deg,
                  k.lower_deg, k.upper_deg);
    if (f.test.frames)
      StringAppendf(&text, "  %.3f%%", 100.0 * f.test.violations[c] / f.test.frames);
    text += "\n";
  }
  if (f.test.frames) {
    StringAppendf(&text, "test split: %s frames, %.3f%% outside some range or undefined\n",
                  WithThousands(f.test.frames).c_str(), 100.0 * f.test.flagged / f.test.frames);
  }
  if (!f.left_out.empty()) AppendLeftOut(&text, f);
  return text;
}

std::string ConstraintFitCommandLine(const ConstraintFitRequest& o, const std::string& out) {
  const FitOptions defaults;
  std::string cmd =
      "motionfork constraints fit --protocol " + o.protocol + " --data " + o.data + " -o " + out;
  if (!o.constraints.empty()) cmd += " --constraints " + o.constraints;
  if (!o.split_file.empty()) cmd += " --split " + o.split_file;
  if (o.fit.low_percentile != defaults.low_percentile)
    cmd += StringPrintf(" --low %g", o.fit.low_percentile);
  if (o.fit.high_percentile != defaults.high_percentile)
    cmd += StringPrintf(" --high %g", o.fit.high_percentile);
  if (o.fit.margin_deg != defaults.margin_deg)
    cmd += StringPrintf(" --margin %g", o.fit.margin_deg);
  if (o.fit.round_deg != defaults.round_deg) cmd += StringPrintf(" --round %g", o.fit.round_deg);
  if (o.leave_one_out) cmd += " --leave-one-out";
  return cmd;
}

}  // namespace motionfork::pipeline
