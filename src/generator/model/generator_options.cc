#include "generator/model/generator_options.h"

#include <stdexcept>
#include <string>

namespace motionfork {

void ValidateGeneratorOptions(const GeneratorOptions& o) {
  auto bad = [](const std::string& field, double value, const std::string& rule) {
    throw std::invalid_argument("generator: " + field + " = " + std::to_string(value) +
                                " breaks the rule: " + rule);
  };
  if (o.num_nodes < 1) bad("num_nodes", o.num_nodes, "must be >= 1 (joints without the root)");
  if (o.t_his < 1) bad("t_his", o.t_his, "must be >= 1 frame");
  if (o.t_pred < 1) bad("t_pred", o.t_pred, "must be >= 1 frame");
  if (o.n_pre < 1 || o.n_pre > o.num_frames()) {
    bad("n_pre", o.n_pre, "must be in 1..t_his + t_pred (" + std::to_string(o.num_frames()) + ")");
  }
  if (o.hidden < 1) bad("hidden", o.hidden, "must be >= 1");
  if (o.blocks < 0) bad("blocks", o.blocks, "must be >= 0");
  if (o.nz < 1) bad("nz", o.nz, "must be >= 1");
  if (o.dropout < 0 || o.dropout >= 1) bad("dropout", o.dropout, "must be in [0, 1)");
  // Upper bounds: a damaged or hostile model.yaml must not make the loader allocate gigabytes
  // before the weights are compared with it.
  if (o.num_nodes > kMaxGeneratorNodes) bad("num_nodes", o.num_nodes, "must be <= 1000");
  if (o.num_frames() > kMaxGeneratorFrames) {
    bad("t_his + t_pred", o.num_frames(), "must be <= " + std::to_string(kMaxGeneratorFrames));
  }
  if (o.hidden > kMaxGeneratorWidth) bad("hidden", o.hidden, "must be <= 4096");
  if (o.nz > kMaxGeneratorWidth) bad("nz", o.nz, "must be <= 4096");
  if (o.blocks > kMaxGeneratorBlocks) bad("blocks", o.blocks, "must be <= 100");
  const double weights = (2.0 * o.blocks + 2) * o.hidden * double(o.hidden);
  if (weights > kMaxGeneratorPartWeights) {
    bad("(2 x blocks + 2) x hidden^2", weights,
        "the graph-conv weights of one body part must be <= " +
            std::to_string(kMaxGeneratorPartWeights) + " numbers");
  }
  if (o.partition.empty())
    throw std::invalid_argument("generator: partition must name a partition");
}

}  // namespace motionfork
