#include "imputation/training/hgvae_evaluation_text.h"

#include <cmath>

#include "core/text_format.h"
#include "eval/history_forecasting_text.h"

namespace motionfork {
namespace {

void AppendLikelihood(std::string* s, const HgvaeLikelihood& l) {
  StringAppendf(s,
                "\nlikelihood (nats per window, densities in metres): ELBO %.1f, reconstruction "
                "MSE %.3g cm^2 (posterior means; %.3g sampled), KL",
                l.elbo_nats, 1e4 * l.recon_mse_m2, 1e4 * l.recon_mse_sampled_m2);
  for (double kl : l.kl_levels) StringAppendf(s, " %.1f", kl);
  StringAppendf(s, " (total %.1f); posterior score %.1f, joint score %.1f\n", l.kl_total,
                l.posterior_score_mean, l.joint_score_mean);
}

void AppendImputation(std::string* s, const HgvaeEvaluation& e, const ImputeOptions& options) {
  StringAppendf(s,
                "\nimputation (%d Adam steps, lr %.3g, %s objective): MSE per missing value, "
                "cm^2\n",
                options.steps, options.learning_rate, ToString(options.objective));
  StringAppendf(s, "  %-12s %10s %10s %10s %10s   score mean-filled -> imputed\n", "occlusion",
                "missing", "mean", "HG-VAE", "reduction");
  for (const ImputationFigure& x : e.imputation) {
    StringAppendf(s, "  %-12s %10lld %10.3f %10.3f %9.1f%%   %.1f -> %.1f\n",
                  x.occlusion.name.c_str(), static_cast<long long>(x.missing_values),
                  1e4 * x.mse_mean, 1e4 * x.mse_model, 100 * x.reduction, x.score_before,
                  x.score_after);
  }
}

void AppendGaps(std::string* s, const HgvaeEvaluation& e) {
  StringAppendf(
      s,
      "\nimputation over %d whole test clips: RMS error of the filled values, cm (mean: "
      "the training mean pose;\nlinear, spline: in time; rigid limb: bone lengths kept;\nhg-vae: "
      "its Adam steps from the mean, hg-vae+spline: from the spline; refiner: the bundle's refiner)"
      "\n  %-26s %7s",
      e.gap_clips, "missing", "clips");
  for (FillMethod m : AllFillMethods()) StringAppendf(s, " %10s", FillMethodName(m).c_str());
  StringAppendf(s, "   best baseline\n");
  for (const GapFigure& g : e.gaps) {
    StringAppendf(s, "  %-26s %7d", g.setting.name.c_str(), g.motions);
    for (double v : g.rms_cm) {
      if (std::isnan(v))
        StringAppendf(s, " %10s", "-");  // the refiner, where the bundle has none
      else
        StringAppendf(s, " %10.3f", v);
    }
    const int b = g.best_baseline();
    StringAppendf(s, "   %s\n", b < 0 ? "-" : FillMethodName(AllFillMethods()[b]).c_str());
  }
}

void AppendOod(std::string* s, const HgvaeEvaluation& e, const HgvaeModel& model) {
  StringAppendf(s,
                "\nout of distribution: AUROC (clean vs degraded) of the joint and the posterior "
                "score; share flagged by the bundle's rule (%s score < %.1f)\n",
                ToString(model.manifest().ood_score), model.OodThreshold());
  StringAppendf(s, "  %-22s %12s %12s %8s\n", "windows", "AUROC joint", "posterior", "flagged");
  StringAppendf(s, "  %-22s %12s %12s %7.1f%%\n", "clean", "-", "-", 100.0 * e.clean_flagged);
  for (const OodTest& t : e.ood) {
    StringAppendf(s, "  %-22s %12.4f %12.4f %7.1f%%\n", t.degradation.c_str(), t.auroc_joint,
                  t.auroc_posterior, 100.0 * t.flagged);
  }
}

}  // namespace

std::string HgvaeEvaluationText(const HgvaeEvaluation& e, const HgvaeModel& model,
                                const std::string& model_path, const ImputeOptions& impute) {
  const HgvaeManifest& m = model.manifest();
  std::string s = StringPrintf(
      "HG-VAE %s (%s parameters, %zu levels, %d stochastic) on the %s test split: %d windows of "
      "%d frames\n",
      model_path.c_str(), WithThousands(model.num_parameters()).c_str(), m.model.levels.size(),
      e.stochastic_levels, m.protocol.c_str(), e.windows, e.window_frames);
  if (e.slow != 1) StringAppendf(&s, "test clips played %g times slower\n", e.slow);
  AppendLikelihood(&s, e.likelihood);
  if (!e.likelihood_only) {
    AppendImputation(&s, e, impute);
    if (!e.gaps.empty()) AppendGaps(&s, e);
    AppendOod(&s, e, model);
  }
  if (e.forecasting) {
    const ForecastingFigures& f = *e.forecasting;
    StringAppendf(&s,
                  "\nforecasting (%s, K = %d, %d test windows, raw network output): ADE / FDE "
                  "from the histories\n(HG-VAE: window imputation, 10 steps where the options "
                  "say 0; linear, spline, rigid limb, refiner: filled over the history alone)\n",
                  f.forecaster.c_str(), f.k, f.windows);
    StringAppendf(&s, "  %-12s clean %.3f / %.3f\n", "", f.clean.ade, f.clean.fde);
    s += RepairedForecastsText(f, 12, "mean-imputed", "HG-VAE-imputed");
  }
  return s;
}

}  // namespace motionfork
