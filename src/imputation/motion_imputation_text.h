// Whole-motion imputation and scoring (motion_imputation.h) as text for people: what `motionfork
// impute` and `motionfork ood` print. The same as JSON: motion_imputation_json.h.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"

namespace motionfork {

// How many of the motion's `total_values` values were imputed, in how many windows, with which
// options, the windows' scores before and after, and where the result went (`input` -> `out`;
// a motion with nothing missing: that it was written unchanged).
std::string MotionImputationText(const HgvaeModel& model, const MotionImputation& r,
                                 size_t total_values, const ImputeOptions& options,
                                 const std::string& input, const std::string& out);

// What `motionfork hgvae sample` wrote: count windows (of class `cls`, "" none) to `out`.
std::string SampledMotionText(const HgvaeModel& model, int count, const std::string& cls,
                              const std::string& out);

// A row per window (frames, score, flagged or not), then how many the bundle's rule flags.
std::string WindowScoresText(const HgvaeModel& model, const std::vector<WindowScore>& scores);

}  // namespace motionfork
