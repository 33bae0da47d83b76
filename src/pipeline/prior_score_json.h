// `motionfork prior score`'s report as JSON: a motion's poses under a pose prior
// (prior_score.h).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "core/motion.h"
#include "flow/pose_prior.h"
#include "pipeline/prior_score.h"

namespace motionfork::pipeline {

// The per-frame NLL and its summary; motion: as scored (on the prior's skeleton); file, model: as
// the user named them.
nlohmann::ordered_json PriorScoreJson(const std::string& file, const std::string& model,
                                      const PosePrior& prior, const Motion& motion,
                                      const PriorScore& s);

}  // namespace motionfork::pipeline
