// `motionfork check`'s report as text for people: a motion's frames against angle ranges
// (constraint_check.h). The same as JSON: constraint_check_json.h.
#pragma once

#include <string>

#include "pipeline/constraint_check.h"

namespace motionfork::pipeline {

// The motion, the set and the share of valid frames, a row per constraint, the worst frames with
// their angles, and a note when some angle was undefined; file: as the user named it.
std::string ConstraintCheckText(const std::string& file, const ConstraintCheck& check);

}  // namespace motionfork::pipeline
