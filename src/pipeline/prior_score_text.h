// `motionfork prior score`'s report as text for people: a motion's poses under a pose prior
// (prior_score.h). The same as JSON: prior_score_json.h.
#pragma once

#include <string>

#include "core/motion.h"
#include "flow/pose_prior.h"
#include "pipeline/prior_score.h"

namespace motionfork::pipeline {

// The file and the prior, the per-frame NLL table (per_frame) and the summary; motion: as scored
// (on the prior's skeleton); file, model: as the user named them.
std::string PriorScoreText(const std::string& file, const std::string& model,
                           const PosePrior& prior, const Motion& motion, const PriorScore& s,
                           bool per_frame);

// What `motionfork prior sample` wrote: how many poses, on which skeleton, where.
std::string PriorSampleText(const PosePrior& prior, int count, const std::string& out);

}  // namespace motionfork::pipeline
