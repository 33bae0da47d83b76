// The forecasting figures of repaired histories (history_forecasting.h) as JSON, for the reports
// of the HG-VAE's and the Motion-DVAE's evaluation experiments.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "eval/history_forecasting.h"

namespace motionfork {

// setting_key names each setting; before/after suffix its ADE and FDE keys (e.g. "occlusion",
// "mean_imputed", "hgvae_imputed").
nlohmann::ordered_json ForecastingJson(const ForecastingFigures& f, const std::string& setting_key,
                                       const std::string& before, const std::string& after);

}  // namespace motionfork
