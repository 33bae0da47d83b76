// The `motionfork hgvae eval` report as JSON: an HG-VAE's figures (hgvae_evaluation.h).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "imputation/hgvae_model.h"
#include "imputation/training/hgvae_evaluation.h"

namespace motionfork {

// Likelihood, imputation (with the settings it ran with), out-of-distribution tests and
// forecasting when measured; model_path: the bundle as the user named it.
nlohmann::ordered_json HgvaeEvaluationJson(const HgvaeEvaluation& e, const HgvaeModel& model,
                                           const std::string& model_path,
                                           const ImputeOptions& impute);

}  // namespace motionfork
