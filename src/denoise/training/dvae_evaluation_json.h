// The `motionfork dvae eval` report as JSON: a Motion-DVAE's denoising figures
// (dvae_evaluation.h).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "denoise/training/dvae_evaluation.h"

namespace motionfork {

// Every noise kind's row, speed and forecasting when measured; model_path: the bundle as the user
// named it.
nlohmann::ordered_json DvaeEvaluationJson(const DvaeEvaluation& e, const std::string& model_path);

}  // namespace motionfork
