#include "pipeline/constraint_check_text.h"

#include <algorithm>

#include "core/text_format.h"

namespace motionfork::pipeline {
namespace {

std::string Percent(double share) { return StringPrintf("%.2f%%", 100.0 * share); }

}  // namespace

std::string ConstraintCheckText(const std::string& file, const ConstraintCheck& b) {
  std::string text;
  const ConstraintSet& set = *b.set;
  const CheckSummary& s = b.summary;
  const CheckResult& r = b.result;
  const Motion& m = b.motion;
  StringAppendf(&text, "motion:       %s (skeleton %s, %d joints, %s frames at %.6g Hz)\n",
                file.c_str(), m.skeleton().name().c_str(), m.num_joints(),
                WithThousands(s.frames).c_str(), m.fps());
  StringAppendf(&text, "constraints:  %s (%s), %d angles\n", set.name().c_str(), b.path.c_str(),
                set.num_constraints());
  StringAppendf(&text,
                "valid frames: %s of %s (%s); %s violate a range, %s have an undefined angle\n\n",
                WithThousands(s.valid_frames).c_str(), WithThousands(s.frames).c_str(),
                Percent(s.valid_frame_share()).c_str(), WithThousands(s.violating_frames).c_str(),
                WithThousands(s.degenerate_frames).c_str());
  size_t width = 10;
  for (const Constraint& c : set.constraints()) width = std::max(width, c.name.size());
  const int w = static_cast<int>(width);
  StringAppendf(&text, "%-*s  %15s  %9s  %8s  %7s  %7s  %9s  %7s  %7s  %s\n", w, "constraint",
                "range (deg)", "violated", "rate", "below", "above", "undefined", "min", "max",
                "worst frame");
  for (int c = 0; c < set.num_constraints(); ++c) {
    const Constraint& k = set.constraint(c);
    const ConstraintSummary& cs = s.constraints[c];
    const std::string range = StringPrintf("[%5.1f, %5.1f]", k.lower_deg, k.upper_deg);
    const bool any_defined = cs.degenerate < s.frames;
    const std::string lo = any_defined ? StringPrintf("%.1f", cs.min_deg) : "-";
    const std::string hi = any_defined ? StringPrintf("%.1f", cs.max_deg) : "-";
    const std::string worst =
        cs.worst_frame >= 0 ? StringPrintf("%d (%.1f deg out)", cs.worst_frame, cs.worst_excess_deg)
                            : "-";
    StringAppendf(&text, "%-*s  %15s  %9s  %8s  %7s  %7s  %9s  %7s  %7s  %s\n", w, k.name.c_str(),
                  range.c_str(), WithThousands(cs.violations()).c_str(),
                  Percent(cs.violation_rate).c_str(), WithThousands(cs.below).c_str(),
                  WithThousands(cs.above).c_str(), WithThousands(cs.degenerate).c_str(), lo.c_str(),
                  hi.c_str(), worst.c_str());
  }
  if (!s.worst_frames.empty()) {
    StringAppendf(&text, "\nworst frames (degrees outside the ranges, summed):\n");
    for (const FrameViolation& fv : s.worst_frames) {
      StringAppendf(&text, "  frame %d (%.2f s), %.1f deg:", fv.frame, fv.frame / m.fps(),
                    fv.excess_deg);
      for (size_t i = 0; i < fv.constraints.size(); ++i) {
        const Constraint& c = set.constraint(fv.constraints[i]);
        const float a = r.angle(fv.frame, fv.constraints[i]);
        StringAppendf(&text, "%s %s %.1f (%s %.1f)", i ? "," : "", c.name.c_str(), a,
                      a < c.lower_deg ? "<" : ">", a < c.lower_deg ? c.lower_deg : c.upper_deg);
      }
      text += "\n";
    }
  }
  if (s.degenerate_frames > 0) {
    StringAppendf(&text,
                  "\nundefined angles come from zero-length bones or collinear plane vectors; such "
                  "frames do not count as valid\n");
  }
  return text;
}

}  // namespace motionfork::pipeline
