// The `motionfork eval` report as text for people: the protocol, test windows, predictor and
// samples, then the table of figures overall and per action and the time it took. The same figures
// as JSON: eval_experiment_json.h.
#pragma once

#include <string>

#include "generator/training/eval_experiment.h"

namespace motionfork {

// options: as the experiment ran (its K and seed are reported).
std::string EvalExperimentText(const EvalExperimentOptions& options, const EvalExperiment& x);

}  // namespace motionfork
