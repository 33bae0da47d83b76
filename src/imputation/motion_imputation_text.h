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
// options, and the windows' scores before and after (r holds at least one imputed value).
std::string MotionImputationText(const HgvaeModel& model, const MotionImputation& r,
                                 size_t total_values, const ImputeOptions& options);

// A row per window (frames, score, flagged or not), then how many the bundle's rule flags.
std::string WindowScoresText(const HgvaeModel& model, const std::vector<WindowScore>& scores);

}  // namespace motionfork
