#include "pipeline/prior_score_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "io/json_members.h"

namespace motionfork::pipeline {

using json = nlohmann::ordered_json;

json PriorScoreJson(const std::string& file, const std::string& model, const PosePrior& prior,
                    const Motion& motion, const PriorScore& s) {
  json summary;
  MOTIONFORK_JSON_MEMBERS(summary, s, mean, median, min, best_frame, max, worst_frame, held_out_q50,
                          held_out_q99);
  summary["frames_above_held_out_q99"] = std::isfinite(s.held_out_q99) ? json(s.above_q99) : json();
  return {{"file", file},
          {"model", model},
          {"skeleton", prior.skeleton().name()},
          {"frames", static_cast<int>(s.nll.size())},
          {"fps", motion.fps()},
          {"unit", "nats per pose"},
          {"nll", s.nll},
          {"summary", summary}};
}

}  // namespace motionfork::pipeline
