#include "pipeline/constraint_check_json.h"

#include <nlohmann/json.hpp>

namespace motionfork::pipeline {
namespace {

using json = nlohmann::ordered_json;

json ConstraintJson(const Constraint& k, const ConstraintSummary& cs, int frames) {
  const bool any_defined = cs.degenerate < frames;
  return {{"name", k.name},
          {"side", ToString(k.side)},
          {"a", k.a_text},
          {"b", k.b_text},
          {"lower_deg", k.lower_deg},
          {"upper_deg", k.upper_deg},
          {"violations", cs.violations()},
          {"violation_rate", cs.violation_rate},
          {"below", cs.below},
          {"above", cs.above},
          {"degenerate", cs.degenerate},
          {"min_deg", any_defined ? json(cs.min_deg) : json()},
          {"max_deg", any_defined ? json(cs.max_deg) : json()},
          {"worst_frame", cs.worst_frame >= 0 ? json(cs.worst_frame) : json()},
          {"worst_excess_deg", cs.worst_excess_deg}};
}

json FrameViolationJson(const FrameViolation& fv, const ConstraintCheck& b) {
  const ConstraintSet& set = *b.set;
  json violations = json::array();
  for (int c : fv.constraints) {
    violations.push_back({{"constraint", set.constraint(c).name},
                          {"angle_deg", b.result.angle(fv.frame, c)},
                          {"lower_deg", set.constraint(c).lower_deg},
                          {"upper_deg", set.constraint(c).upper_deg}});
  }
  return {{"frame", fv.frame},
          {"time_s", fv.frame / b.motion.fps()},
          {"excess_deg", fv.excess_deg},
          {"violations", violations}};
}

}  // namespace

json ConstraintCheckJson(const std::string& file, const ConstraintCheck& b) {
  const ConstraintSet& set = *b.set;
  const CheckSummary& s = b.summary;
  json constraints = json::array(), worst = json::array();
  for (int c = 0; c < set.num_constraints(); ++c) {
    constraints.push_back(ConstraintJson(set.constraint(c), s.constraints[c], s.frames));
  }
  for (const FrameViolation& fv : s.worst_frames) worst.push_back(FrameViolationJson(fv, b));
  return {{"file", file},
          {"skeleton", b.motion.skeleton().name()},
          {"constraint_set", set.name()},
          {"constraints_file", b.path},
          {"fps", b.motion.fps()},
          {"frames", s.frames},
          {"valid_frames", s.valid_frames},
          {"valid_frame_share", s.valid_frame_share()},
          {"violating_frames", s.violating_frames},
          {"violating_frame_share", s.frames ? double(s.violating_frames) / s.frames : 0},
          {"degenerate_frames", s.degenerate_frames},
          {"constraints", constraints},
          {"worst_frames", worst}};
}

}  // namespace motionfork::pipeline
