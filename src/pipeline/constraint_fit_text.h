// `motionfork constraints fit`'s report as text for people: the ranges fitted on a protocol's
// training frames and, when the protocol has a test split, how often its frames break them
// (constraint_fit.h).
#pragma once

#include <string>

#include "pipeline/constraint_fit.h"

namespace motionfork::pipeline {

std::string ConstraintFitText(const ConstraintFit& fit);

// The `motionfork constraints fit` command that reproduces a fit written to `out` (options at
// their defaults left out), for the written file's header.
std::string ConstraintFitCommandLine(const ConstraintFitRequest& request, const std::string& out);

}  // namespace motionfork::pipeline
