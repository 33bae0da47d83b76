#include "pipeline/predict_text.h"

#include "core/text_format.h"
#include "pipeline/history_check.h"

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

std::string HistoryDoubtsText(const Prediction& p) {
  std::string s;
  if (!p.history_check) return s;
  for (const std::string& d : p.history_check->doubts) {
    if (d.rfind(kReadingDoubt, 0) == 0) continue;  // printed with the file's notes
    StringAppendf(&s,
                  "warning: %s: the history (frames %d..%d) is far from what the model knows: "
                  "%s; its futures are not marked valid\n",
                  p.history.c_str(), p.start_frame, p.start_frame + p.t_his - 1, d.c_str());
  }
  return s;
}

std::string PredictionWrittenText(const Prediction& p, const std::string& base,
                                  const PredictNotes& notes) {
  std::string s =
      StringPrintf("wrote %s.npy [%d, %d, %d, 3] (history + %d futures, %.6g Hz) and %s.json\n",
                   base.c_str(), p.k, p.frames(), p.joints(), p.k, p.fps, base.c_str());
  const ValiditySummary v = Summarise(p);
  if (notes.angle_ranges || notes.prior) {
    std::string judges = notes.angle_ranges ? "angle ranges" : "";
    if (notes.prior) {
      judges += std::string(judges.empty() ? "" : ", ") + "prior NLL" +
                (p.prior_bound ? StringPrintf(" <= %.4g", *p.prior_bound) : std::string());
    }
    StringAppendf(&s, "validity: %d of %d futures valid (%s)", v.valid_futures, p.k,
                  judges.c_str());
    std::string failing;
    const auto add = [&](int n, const char* what) {
      if (n > 0) failing += StringPrintf("%s%d %s", failing.empty() ? "" : ", ", n, what);
    };
    add(v.failing_angles, "outside the angle ranges");
    add(v.failing_prior, "above the prior's bound");
    add(v.failing_history, "from a doubted history");
    s += failing.empty() ? "\n" : "; " + failing + "\n";
  }
  if (notes.angle_ranges) {
    StringAppendf(&s, "angle ranges: history %d of %d frames violate\n",
                  p.history_validity->violating_frames, p.t_his);
  }
  if (notes.prior) {
    StringAppendf(&s, "prior NLL: futures %.2f nats per pose (mean), history %.2f\n",
                  v.mean_prior_nll, *p.history_validity->prior_nll);
  }
  if (!notes.angle_ranges && !notes.prior) {
    s += "no validity figures: the bundle carries no constraints.yaml or prior/\n";
  }
  if (const auto& c = p.history_check) {
    if (c->window_score) {
      StringAppendf(&s, "history: HG-VAE window score %.4g (out of distribution below %.4g)\n",
                    *c->window_score, c->window_bound.value_or(0.0));
    }
    if (c->doubts.empty()) s += "history: no doubt (size, axis, left/right, bones, judges)\n";
  }
  return s;
}

}  // namespace motionfork::pipeline
