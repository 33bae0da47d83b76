#include "imputation/motion_imputation_text.h"

#include <cmath>

#include "core/text_format.h"
#include "imputation/motion_imputation_summary.h"

namespace motionfork {

std::string MotionImputationText(const HgvaeModel& model, const MotionImputation& r,
                                 size_t total_values, const ImputeOptions& options,
                                 const std::string& input, const std::string& out) {
  if (r.missing_values == 0) {
    return StringPrintf("no missing values in %s (no NaN, no --mask): wrote it unchanged to %s\n",
                        input.c_str(), out.c_str());
  }
  const ImputationScoreSummary scores = SummariseScores(model, r);
  const HgvaeManifest& m = model.manifest();
  std::string s = StringPrintf(
      "imputed %d of %zu values (%.1f%%) in %zu windows of %d frames (%d Adam steps, %s "
      "objective)\n",
      r.missing_values, total_values, 100.0 * r.missing_values / total_values,
      r.window_starts.size(), model.window(), options.steps, ToString(options.objective));
  StringAppendf(&s,
                "%s score per window: %.1f with the training mean -> %.1f imputed (training "
                "windows: %.1f +- %.1f); out of distribution: %d -> %d windows\n",
                ToString(m.ood_score), scores.mean_before, scores.mean_after, m.score_mean,
                m.score_std, scores.ood_before, scores.ood_after);
  StringAppendf(&s, "wrote %s (%d frames, %.6g Hz)\n", out.c_str(), r.motion.num_frames(),
                r.motion.fps());
  return s;
}

std::string SampledMotionText(const HgvaeModel& model, int count, const std::string& cls,
                              const std::string& out) {
  return StringPrintf(
      "wrote %s: %d sample%s of %d frames (%.6g Hz) one after another%s, root at the origin\n",
      out.c_str(), count, count == 1 ? "" : "s", model.window(), model.manifest().fps,
      cls.empty() ? "" : (", class '" + cls + "'").c_str());
}

std::string WindowScoresText(const HgvaeModel& model, const std::vector<WindowScore>& scores) {
  const HgvaeManifest& m = model.manifest();
  std::string s = StringPrintf("window  frames       score   out of distribution (threshold %ld)\n",
                               std::lround(model.OodThreshold()));
  for (size_t w = 0; w < scores.size(); ++w) {
    const WindowScore& x = scores[w];
    StringAppendf(&s, "%6zu  %5d-%-5d %9.1f   %s\n", w, x.start, x.start + model.window() - 1,
                  x.score, x.out_of_distribution ? "yes" : "no");
  }
  StringAppendf(&s,
                "%d of %zu windows out of distribution (%s score below the training windows' "
                "mean %.1f - %.3g x std %.1f)\n",
                CountOutOfDistribution(scores), scores.size(), ToString(m.ood_score), m.score_mean,
                m.ood_k, m.score_std);
  return s;
}

}  // namespace motionfork
