#include "pipeline/predict_text.h"

#include "core/text_format.h"

namespace motionfork::pipeline {

std::string PredictionRepairsText(const Prediction& p) {
  std::string s;
  if (const auto& im = p.imputation) {
    StringAppendf(
        &s,
        "imputed %d missing history values with %s (%s score %.1f -> %.1f; training windows %.1f "
        "+- %.1f)\n",
        im->missing_values, im->model.c_str(), im->score_kind.c_str(), im->score_before,
        im->score_after, im->training_mean, im->training_std);
  }
  if (const auto& d = p.denoising) {
    StringAppendf(
        &s,
        "denoised the history with %s (%s mode, frames %d..%d): mean change %.2f cm per joint\n",
        d->model.c_str(), d->mode.c_str(), d->first_frame, p.start_frame + p.t_his - 1,
        100 * d->mean_change);
  }
  return s;
}

std::string PredictionWrittenText(const Prediction& p, const std::string& base,
                                  const PredictNotes& notes) {
  std::string s =
      StringPrintf("wrote %s.npy [%d, %d, %d, 3] (history + %d futures, %.6g Hz) and %s.json\n",
                   base.c_str(), p.k, p.frames(), p.joints(), p.k, p.fps, base.c_str());
  const ValiditySummary v = Summarise(p);
  if (notes.angle_ranges) {
    StringAppendf(
        &s,
        "angle ranges: %d of %d futures valid in every frame (history: %d of %d frames violate)\n",
        v.valid_futures, p.k, p.history_validity->violating_frames, p.t_his);
  }
  if (notes.prior) {
    StringAppendf(&s, "prior NLL: futures %.2f nats per pose (mean), history %.2f\n",
                  v.mean_prior_nll, *p.history_validity->prior_nll);
  }
  if (!notes.angle_ranges && !notes.prior) {
    s += "no validity figures: the bundle carries no constraints.yaml or prior/\n";
  }
  return s;
}

}  // namespace motionfork::pipeline
