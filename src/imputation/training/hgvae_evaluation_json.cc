#include "imputation/training/hgvae_evaluation_json.h"

#include <nlohmann/json.hpp>

#include "eval/history_forecasting_json.h"

namespace motionfork {

// Keys in alphabetical order (nlohmann::json's), as the reports have always had them.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(HgvaeLikelihood, elbo_nats, recon_mse_m2, recon_mse_sampled_m2,
                                   kl_levels, kl_total, posterior_score_mean, joint_score_mean)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(OodTest, degradation, auroc_joint, auroc_posterior, flagged)

namespace {

using json = nlohmann::ordered_json;

json ImputationJson(const HgvaeEvaluation& e, const ImputeOptions& options) {
  json settings = json::array();
  for (const ImputationFigure& x : e.imputation) {
    settings.push_back({{"occlusion", x.occlusion.name},
                        {"share", x.occlusion.share},
                        {"missing_values", x.missing_values},
                        {"mse_mean_m2", x.mse_mean},
                        {"mse_hgvae_m2", x.mse_model},
                        {"reduction", x.reduction},
                        {"score_mean_filled", x.score_before},
                        {"score_imputed", x.score_after}});
  }
  return {{"steps", options.steps},
          {"learning_rate", options.learning_rate},
          {"objective", ToString(options.objective)},
          {"settings", settings}};
}

json GapsJson(const HgvaeEvaluation& e) {
  json settings = json::array();
  for (const GapFigure& g : e.gaps) {
    json rms = json::object();
    for (size_t m = 0; m < g.rms_cm.size(); ++m)
      rms[FillMethodName(AllFillMethods()[m])] = g.rms_cm[m];
    settings.push_back(
        {{"setting", g.setting.name},
         {"clips", g.motions},
         {"missing_values", g.missing_values},
         {"rms_cm", rms},
         {"best_baseline", g.best_baseline() < 0
                               ? std::string()
                               : FillMethodName(AllFillMethods()[g.best_baseline()])}});
  }
  return {{"clips", e.gap_clips}, {"settings", settings}};
}

}  // namespace

json HgvaeEvaluationJson(const HgvaeEvaluation& e, const HgvaeModel& model,
                         const std::string& model_path, const ImputeOptions& impute) {
  json j = {{"model", model_path},
            {"protocol", model.manifest().protocol},
            {"windows", e.windows},
            {"window_frames", e.window_frames},
            {"parameters", model.num_parameters()},
            {"stochastic_levels", e.stochastic_levels},
            {"likelihood", json(nlohmann::json(e.likelihood))}};
  if (e.slow != 1) j["slow"] = e.slow;
  if (!e.likelihood_only) {
    j["imputation"] = ImputationJson(e, impute);
    if (!e.gaps.empty()) j["gaps"] = GapsJson(e);
    j["ood"] = {{"score", ToString(model.manifest().ood_score)},
                {"threshold", model.OodThreshold()},
                {"clean_flagged", e.clean_flagged},
                {"tests", json(nlohmann::json(e.ood))}};
  }
  if (e.forecasting) {
    j["forecasting"] =
        ForecastingJson(*e.forecasting, "occlusion", "mean_imputed", "hgvae_imputed");
  }
  return j;
}

}  // namespace motionfork
