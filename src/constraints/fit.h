// Fitting angle ranges from data: for every constraint of a set, a low and a high percentile of
// its angle over training frames, widened by a margin. Both instances of a per-side constraint
// are pooled (they measure the same anatomical angle), so the fitted range is symmetric.
#pragma once

#include <string>
#include <vector>

#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "core/motion.h"

namespace motionfork {

// The defaults (the whole training range plus 5 degrees) were chosen by leaving each Bandai
// training style out in turn: percentiles 0.1 / 99.9 + 2 degrees flagged up to 21.7% of a left-out
// style's real frames, these 0.28% (RESULTS.md, "Validity").
struct FitOptions {
  double low_percentile = 0;     // percent (0..100) of defined angles left below the lower bound
  double high_percentile = 100;  // percent (0..100), > low_percentile
  double margin_deg = 5.0;  // degrees added outside both percentiles; result clamped to [0, 180]
  double round_deg = 0.1;   // bounds rounded outwards to a multiple of this (0 = no rounding)
  DegeneracyOptions degeneracy;  // undefined angles are skipped (and counted)
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const FitOptions& options);

struct FittedRange {
  std::string name;           // the spec constraint (per-side instances pooled)
  long long samples = 0;      // defined angles used (frames x instances)
  long long degenerate = 0;   // undefined angles skipped
  double low_value_deg = 0;   // the low percentile, before margin and rounding
  double high_value_deg = 0;  // the high percentile, before margin and rounding
  double lower_deg = 0;       // fitted range, degrees
  double upper_deg = 180;
  bool widened = false;  // the range was widened to the constraint's anatomical limit
};

// Accumulates angles frame by frame (keeps them: 4 bytes per frame and instance), then fits.
class RangeFitter {
 public:
  RangeFitter(const ConstraintSet& set, const FitOptions& options = {});

  // positions: [num_frames, J, 3] metres, J = set.num_joints().
  void Add(const float* positions, int num_frames);
  // Throws std::invalid_argument when the joint count differs from the set's.
  void Add(const Motion& motion);
  long long frames() const { return frames_; }
  // Adds the angles another fitter of the same constraint set has gathered (e.g. one fitter per
  // subject, merged for a leave-one-out fit). Throws std::invalid_argument for another set.
  void Merge(const RangeFitter& other);

  // One range per spec constraint, in spec order. Throws std::invalid_argument naming the
  // constraint when it has no defined angle at all.
  std::vector<FittedRange> Fit() const;

 private:
  const ConstraintSet& set_;
  FitOptions options_;
  AngleChecker checker_;
  long long frames_ = 0;
  std::vector<std::vector<float>> samples_;  // per spec constraint
  std::vector<long long> degenerate_;        // per spec constraint
  std::vector<float> angles_;                // scratch [T, C]
};

// Percentile (0..100) of values with linear interpolation between order statistics (NumPy's
// default). Reorders values. Throws std::invalid_argument on an empty input.
double Percentile(std::vector<float>* values, double percent);

// spec with each constraint's range replaced by its fitted one (matched by name) and the fit
// statistics as the range comment.
ConstraintSetSpec WithFittedRanges(const ConstraintSetSpec& spec,
                                   const std::vector<FittedRange>& ranges);

}  // namespace motionfork
