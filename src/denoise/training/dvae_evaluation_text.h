// The Motion-DVAE's evaluation (dvae_evaluation.h) as text for people: what `motionfork dvae eval`
// prints, in the pieces it prints as the figures come in. The same figures as JSON:
// dvae_evaluation_json.h.
#pragma once

#include <string>

#include "denoise/dvae_model.h"
#include "denoise/training/dvae_evaluation.h"

namespace motionfork {

// Once the clips are chosen: the model, the test clips and the table's header.
std::string DvaeEvaluationHeaderText(const DvaeEvaluation& e, const DvaeModel& model,
                                     const std::string& model_path);
// One noise kind's row of the table, then a line per filter with its tuned parameters.
std::string DenoisingRowText(const DenoisingRow& r);
// After the last row: what the baseline and optimisation columns mean, the speed on `threads`
// threads, and the forecasting rows when measured.
std::string DvaeEvaluationFooterText(const DvaeEvaluation& e, int threads);

}  // namespace motionfork
