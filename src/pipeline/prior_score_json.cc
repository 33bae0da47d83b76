#include "pipeline/prior_score_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

namespace motionfork::pipeline {

using json = nlohmann::ordered_json;

json PriorScoreJson(const std::string& file, const std::string& model, const PosePrior& prior,
                    const Motion& motion, const PriorScore& s) {
  const bool known = std::isfinite(s.held_out_q99);
  return {{"file", file},
          {"model", model},
          {"skeleton", prior.skeleton().name()},
          {"frames", static_cast<int>(s.nll.size())},
          {"fps", motion.fps()},
          {"unit", "nats per pose"},
          {"nll", s.nll},
          {"summary",
           {{"mean", s.mean},
            {"median", s.median},
            {"min", s.min},
            {"best_frame", s.best_frame},
            {"max", s.max},
            {"worst_frame", s.worst_frame},
            {"held_out_q50", s.held_out_q50},
            {"held_out_q99", s.held_out_q99},
            {"frames_above_held_out_q99", known ? json(s.above_q99) : json()}}}};
}

}  // namespace motionfork::pipeline
