// The HG-VAE's evaluation (hgvae_evaluation.h) as text for people: what `motionfork hgvae eval`
// prints. The same figures as JSON: hgvae_evaluation_json.h.
#pragma once

#include <string>

#include "imputation/hgvae_model.h"
#include "imputation/training/hgvae_evaluation.h"

namespace motionfork {

// The model and test split, then the likelihood, imputation and out-of-distribution tables (the
// latter two unless the evaluation was likelihood-only) and the forecasting rows when measured.
// impute: the options the imputation ran with.
std::string HgvaeEvaluationText(const HgvaeEvaluation& e, const HgvaeModel& model,
                                const std::string& model_path, const ImputeOptions& impute);

}  // namespace motionfork
