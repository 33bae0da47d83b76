#include "imputation/hgvae_options.h"

#include <stdexcept>

namespace motionfork {

const char* ToString(ImputeObjective objective) { return NameOf(objective, kImputeObjectiveNames); }

const char* ToString(ImputeStart start) { return NameOf(start, kImputeStartNames); }

ImputeStart ParseImputeStart(const std::string& text) {
  return ParseEnumName(text, kImputeStartNames, "impute start");
}

ImputeObjective ParseImputeObjective(const std::string& text) {
  return ParseEnumName(text, kImputeObjectiveNames, "impute objective");
}

ImputeOptions ImputeOverrides::Apply(ImputeOptions o) const {
  if (steps >= 0) o.steps = steps;
  if (learning_rate > 0) o.learning_rate = learning_rate;
  if (!objective.empty()) o.objective = ParseImputeObjective(objective);
  if (!start.empty()) o.start = ParseImputeStart(start);
  return o;
}

void ValidateHgvaeOptions(const HgvaeOptions& o, int num_coords) {
  auto fail = [](const std::string& m) { throw std::invalid_argument("hgvae model: " + m); };
  if (o.levels.empty() || o.levels.size() > 16) fail("levels: expected 1 to 16 levels");
  for (size_t l = 0; l < o.levels.size(); ++l) {
    const HgvaeLevel& v = o.levels[l];
    const std::string at = "levels[" + std::to_string(l) + "]";
    if (v.nodes < 0 || v.nodes > 100000 || v.features < 1 || v.features > kMaxHgvaeWidth)
      fail(at + ": expected nodes in 0..100000 and features in 1..4096");
    if (num_coords > 0 && v.nodes > num_coords) {
      fail(at + ": " + std::to_string(v.nodes) + " nodes, more than the " +
           std::to_string(num_coords) + " coordinates of the full graph");
    }
  }
  const int last = o.levels.back().nodes;
  if (last != 0 && (num_coords == 0 || last != num_coords)) {
    fail("the last (bottom) level must be the full graph: nodes 0 (= every coordinate)" +
         (num_coords > 0 ? ", or " + std::to_string(num_coords) : std::string()) + "; got " +
         std::to_string(last));
  }
  if (o.width < 1 || o.width > kMaxHgvaeWidth)
    fail("width: expected 1..4096, got " + std::to_string(o.width));
  if (o.encoder_blocks < 0 || o.decoder_blocks < 0 || o.encoder_blocks > 100 ||
      o.decoder_blocks > 100)
    fail("encoder_blocks/decoder_blocks: expected 0..100");
  if (o.stochastic_levels < 0 || o.stochastic_levels > static_cast<int>(o.levels.size())) {
    fail("stochastic_levels: expected 0 (all) .. " + std::to_string(o.levels.size()) + ", got " +
         std::to_string(o.stochastic_levels));
  }
  if (o.window < 0 || o.window > 4096)
    fail("window: expected 0..4096 frames, got " + std::to_string(o.window));
  if (o.label_dropout < 0 || o.label_dropout >= 1) fail("label_dropout: expected in [0, 1)");
}

HgvaeOptions ResolveHgvaeOptions(HgvaeOptions o, int num_coords, int t_his) {
  for (HgvaeLevel& l : o.levels) {
    if (l.nodes == 0) l.nodes = num_coords;
  }
  if (o.window == 0) o.window = t_his;
  ValidateHgvaeOptions(o, num_coords);
  return o;
}

}  // namespace motionfork
