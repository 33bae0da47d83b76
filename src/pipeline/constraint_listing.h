// A constraint set as `motionfork constraints show` lists it: every angle with its range (or "no
// range yet": definitions not fitted) and the two vectors it is measured between.
#pragma once

#include <string>

namespace motionfork::pipeline {

// constraints: a shipped set's name or a YAML path; skeleton: a name or path, "" = the one the set
// names. Throws std::invalid_argument (FormatError for a malformed file) naming what is wrong.
std::string ConstraintSetListing(const std::string& config_dir, const std::string& constraints,
                                 const std::string& skeleton);

}  // namespace motionfork::pipeline
