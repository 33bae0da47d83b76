// The `motionfork eval` report as JSON: every figure of an evaluation experiment
// (eval_experiment.h), overall and per action, with the settings and the time it took.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "generator/training/eval_experiment.h"

namespace motionfork {

// options: as the experiment ran (its split, clips, K and seed are reported).
nlohmann::ordered_json EvalExperimentJson(const EvalExperimentOptions& options,
                                          const EvalExperiment& x);

}  // namespace motionfork
