#include "pipeline/constraint_fit_text.h"

#include <algorithm>

#include "core/text_format.h"

namespace motionfork::pipeline {

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
                "p_high", "range (deg)", f.test_frames ? "test violations" : "");
  for (int c = 0; c < set.num_constraints(); ++c) {
    const Constraint& k = set.constraint(c);
    const FittedRange& fr = f.ranges[k.spec_index];
    StringAppendf(&text, "%-*s  %12s  %9.2f  %9.2f  [%6.1f, %6.1f]", w, k.name.c_str(),
                  WithThousands(fr.samples).c_str(), fr.low_value_deg, fr.high_value_deg,
                  k.lower_deg, k.upper_deg);
    if (f.test_frames)
      StringAppendf(&text, "  %.3f%%", 100.0 * f.test_violations[c] / f.test_frames);
    text += "\n";
  }
  if (f.test_frames) {
    StringAppendf(&text, "test split: %s frames, %.3f%% outside some range or undefined\n",
                  WithThousands(f.test_frames).c_str(), 100.0 * f.test_invalid / f.test_frames);
  }
  return text;
}

}  // namespace motionfork::pipeline
