#include "imputation/motion_imputation_summary.h"

namespace motionfork {

ImputationScoreSummary SummariseScores(const HgvaeModel& model, const MotionImputation& r) {
  ImputationScoreSummary s;
  for (size_t w = 0; w < r.window_starts.size(); ++w) {
    s.mean_before += r.score_before[w];
    s.mean_after += r.score_after[w];
    s.ood_before += model.OutOfDistribution(r.score_before[w]);
    s.ood_after += model.OutOfDistribution(r.score_after[w]);
  }
  const double n = static_cast<double>(r.window_starts.size());
  s.mean_before /= n;
  s.mean_after /= n;
  return s;
}

int CountOutOfDistribution(const std::vector<WindowScore>& scores) {
  int flagged = 0;
  for (const WindowScore& s : scores) flagged += s.out_of_distribution;
  return flagged;
}

}  // namespace motionfork
