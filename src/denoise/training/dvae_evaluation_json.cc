#include "denoise/training/dvae_evaluation_json.h"

#include <nlohmann/json.hpp>

#include "eval/history_forecasting_json.h"
#include "io/json_members.h"

namespace motionfork {

// Keys in alphabetical order (nlohmann::json's), as the reports have always had them.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FilterFigure, filter, setting, tuning_cm, cm, removed,
                                   accel_ratio)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DenoisingRow, noise, noisy_cm, denoised_cm, removed,
                                   optimised_cm, optimised_noisy_cm, removed_optimised,
                                   accel_ratio_noisy, accel_ratio_denoised, accel_ratio_optimised,
                                   refined_cm, removed_refined, accel_ratio_refined, filters)

nlohmann::ordered_json DvaeEvaluationJson(const DvaeEvaluation& e, const std::string& model_path) {
  using json = nlohmann::ordered_json;
  json j = {{"model", model_path}};
  MOTIONFORK_JSON_MEMBERS(j, e, clips, frames, tuning_clips, tuning_frames, clean_accel, samples,
                          iterations, optimisation_clips, regression_frames_per_s);
  j["settings"] = json(nlohmann::json(e.settings));
  if (e.slow != 1) j["slow"] = e.slow;
  if (e.optimisation_clips > 0) j["optimisation_frames_per_s"] = e.optimisation_frames_per_s;
  if (e.refiner) j["refiner_frames_per_s"] = e.refiner_frames_per_s;
  if (e.forecasting) {
    j["forecasting"] = ForecastingJson(*e.forecasting, "noise", "noisy", "denoised");
  }
  return j;
}

}  // namespace motionfork
