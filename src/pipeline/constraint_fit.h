// `constraints fit`: every constraint's range from the training split of a protocol's data (a low
// and a high percentile of the angle, widened by a margin), as a constraint YAML whose header says
// how it was made, with a first look at the held-out test split.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "constraints/constraint_set.h"
#include "constraints/constraint_spec.h"
#include "constraints/fit.h"
#include "core/progress.h"
#include "dataset/protocol_options.h"

namespace motionfork::pipeline {

struct ConstraintFitRequest {
  std::string protocol;     // name or YAML path
  std::string data;         // the protocol's data folder
  std::string constraints;  // definitions (name or YAML path); "" = named like the skeleton
  std::string split_file;   // "" = the protocol's
  FitOptions fit;
  std::string command_line;  // the command that reproduces the fit, for the file's header
  std::string config_dir, cache_dir;
  StageProgress progress;  // loading, measuring angles
};

struct ConstraintFit {
  ProtocolOptions protocol;
  ConstraintSetSpec definitions;
  std::optional<ConstraintSet> fitted;  // bound to the protocol skeleton
  std::vector<FittedRange> ranges;      // [definitions.constraints.size()]
  long long train_frames = 0, test_frames = 0, test_invalid = 0;
  std::vector<long long> test_violations;  // [fitted constraints]
  std::string yaml;                        // the constraint YAML to write
};

// Throws std::invalid_argument for bad fit options, definitions that do not bind to the
// skeleton (before the dataset is read), or a data folder without training clips.
ConstraintFit FitConstraints(const ConstraintFitRequest& request);

}  // namespace motionfork::pipeline
