// What reports say of whole-motion imputation and scoring (motion_imputation.h): the windows' mean
// score before and after imputation, and how many windows the bundle's rule flags.
#pragma once

#include <vector>

#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"

namespace motionfork {

// Over the windows that held missing values (at least one).
struct ImputationScoreSummary {
  double mean_before = 0, mean_after = 0;  // the score, with the training mean -> imputed
  int ood_before = 0, ood_after = 0;       // windows out of distribution, before -> after
};
ImputationScoreSummary SummariseScores(const HgvaeModel& model, const MotionImputation& r);

// Windows flagged out of distribution.
int CountOutOfDistribution(const std::vector<WindowScore>& scores);

}  // namespace motionfork
