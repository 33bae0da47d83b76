// `motionfork check`'s report as JSON: a motion's frames against a constraint set
// (constraint_check.h).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "pipeline/constraint_check.h"

namespace motionfork::pipeline {

// Frames, valid and violating shares, every constraint's violation rate and the worst frames;
// file: as the user named it.
nlohmann::ordered_json ConstraintCheckJson(const std::string& file, const ConstraintCheck& check);

}  // namespace motionfork::pipeline
