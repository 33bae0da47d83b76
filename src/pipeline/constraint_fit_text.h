// `motionfork constraints fit`'s report as text for people: the ranges fitted on a protocol's
// training frames and, when the protocol has a test split, how often its frames break them
// (constraint_fit.h).
#pragma once

#include <string>

#include "pipeline/constraint_fit.h"

namespace motionfork::pipeline {

std::string ConstraintFitText(const ConstraintFit& fit);

}  // namespace motionfork::pipeline
