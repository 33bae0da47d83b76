#include "flow/flow_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace motionfork {

std::string FlowNumberText(double v) {
  if (std::isnan(v)) return ".nan";
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

PriorSchedule MakePriorSchedule(const PriorTrainOptions& o, int64_t steps_per_epoch) {
  PriorSchedule s{o.epochs, o.constant_epochs, false};
  const int64_t steps = std::max<int64_t>(1, steps_per_epoch);
  if (static_cast<int64_t>(o.epochs) * steps >= o.min_steps) return s;
  s.epochs = static_cast<int>((o.min_steps + steps - 1) / steps);
  s.constant_epochs = static_cast<int>(
      std::lround(static_cast<double>(o.constant_epochs) * s.epochs / std::max(1, o.epochs)));
  s.raised = true;
  return s;
}

std::string FormatFlowConfig(const PriorConfig& c) {
  const FlowOptions& m = c.model;
  const PriorTrainOptions& t = c.training;
  std::string s;
  s += "model:\n";
  s += "  layers: " + std::to_string(m.num_layers) + "\n";
  s += "  reflections: " + std::to_string(m.num_reflections) + "\n";
  s += "  prelu_init: " + FlowNumberText(m.prelu_init) + "\n";
  s += "training:\n";
  s += "  epochs: " + std::to_string(t.epochs) + "\n";
  s += "  constant_epochs: " + std::to_string(t.constant_epochs) + "\n";
  s += "  batch_size: " + std::to_string(t.batch_size) + "\n";
  s += "  learning_rate: " + FlowNumberText(t.learning_rate) + "\n";
  s += "  weight_decay: " + FlowNumberText(t.weight_decay) + "\n";
  s += "  adam_beta1: " + FlowNumberText(t.adam_beta1) + "\n";
  s += "  adam_beta2: " + FlowNumberText(t.adam_beta2) + "\n";
  s += "  adam_eps: " + FlowNumberText(t.adam_eps) + "\n";
  s += "  seed: " + std::to_string(t.seed) + "\n";
  s += "  held_out_share: " + FlowNumberText(t.held_out_share) + "\n";
  s += "  frame_stride: " + std::to_string(t.frame_stride) + "\n";
  s += "  min_steps: " + std::to_string(t.min_steps) + "\n";
  return s;
}

}  // namespace motionfork
