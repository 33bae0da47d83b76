// `check`: a motion's frames against an angle-range constraint set — the set chosen (named, named
// like the motion's skeleton, or the one shipped set whose joints the motion has) and bound to the
// motion, every frame checked and summarised.
#pragma once

#include <optional>
#include <string>

#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "constraints/constraint_spec.h"
#include "core/motion.h"
#include "pipeline/motion_input.h"

namespace motionfork::pipeline {

struct ConstraintCheck {
  std::string path;  // the constraint YAML
  ConstraintSetSpec spec;
  Motion motion;  // as the set sees it (on the set's skeleton config when it names one)
  std::vector<std::string> notes;  // how the motion's joints were mapped onto the set's
  std::optional<ConstraintSet> set;
  CheckResult result;
  CheckSummary summary;
};

// constraints: a shipped name or YAML path; "" = the set named like the loaded motion's skeleton
// config, else the one shipped set (in config_dir) whose joints the motion has. `file` names the
// motion in messages. worst: how many of the worst frames to summarise.
ConstraintCheck CheckMotion(const LoadedMotion& loaded, const std::string& file,
                            const std::string& constraints, const std::string& config_dir,
                            int worst);

// Every frame's angles as CSV: frame, time_s, one column per constraint (degrees; empty =
// undefined).
std::string AnglesCsv(const ConstraintSet& set, const CheckResult& result, double fps);

}  // namespace motionfork::pipeline
