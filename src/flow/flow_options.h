// Options of the pose prior (a normalizing flow on limb directions, GSPS) and the description of a
// saved prior bundle. Plain structs, no LibTorch: src/config parses YAML into them, src/flow uses
// them, apps print them.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace motionfork {

// Architecture: N invertible layers x -> x Q R + b (Q orthogonal, R upper-triangular with a
// positive diagonal), a PReLU with a learnable slope after every layer but the last.
struct FlowOptions {
  // Invertible linear layers (>= 1). GSPS uses 3.
  int num_layers = 3;
  // Householder reflections making each Q (1..dim); 0 = dim, which reaches every rotation.
  int num_reflections = 0;
  // Initial PReLU slope for negative inputs (> 0; the slope is learned as log(slope) so it stays
  // positive and the layer invertible).
  double prelu_init = 0.25;
};

// Training on single frames (negative log-likelihood, Adam). Defaults: GSPS's released code.
struct PriorTrainOptions {
  // Passes over the training frames (>= 1).
  int epochs = 25;
  // Epochs at the full learning rate; afterwards the rate falls linearly per epoch by GSPS's rule
  // lr * (1 - (epoch - constant_epochs) / (epochs - constant_epochs + 1)), epoch counted from 0.
  int constant_epochs = 5;
  // Frames per Adam step (>= 1).
  int batch_size = 4096;
  // Adam learning rate (> 0).
  double learning_rate = 1e-2;
  // L2 penalty added to the gradient (PyTorch Adam's weight_decay, >= 0).
  double weight_decay = 1e-3;
  // Adam moment decay rates (0 <= beta < 1) and epsilon (> 0): PyTorch's defaults.
  double adam_beta1 = 0.9;
  double adam_beta2 = 0.999;
  double adam_eps = 1e-8;
  // Seeds the initial weights, the held-out clips and the order of frames in every epoch.
  uint64_t seed = 0;
  // Share of the training split's clips (whole clips, never single frames: neighbouring frames
  // are near-copies) held out to measure the NLL after every epoch (0 <= share < 1).
  double held_out_share = 0.05;
  // Use every n-th frame of each clip (>= 1); 1 = all frames.
  int frame_stride = 1;
  // At least this many Adam steps in all (>= 0): on a small dataset (few steps an epoch) the
  // epochs are raised to reach it, and constant_epochs in proportion (PriorSchedule). GSPS's 25
  // epochs of batch 4,096 are 1,550 steps on Bandai and 25 on HumanEva-I's 3,596 frames, too few.
  int min_steps = 1500;
};

// The schedule a run follows for `steps_per_epoch` steps an epoch: the options' epochs and
// constant_epochs, raised when epochs x steps_per_epoch < min_steps to the fewest epochs reaching
// min_steps, constant_epochs scaled by the same factor (rounded).
struct PriorSchedule {
  int epochs = 0, constant_epochs = 0;
  bool raised = false;  // the options' epochs gave fewer than min_steps steps
};
PriorSchedule MakePriorSchedule(const PriorTrainOptions& options, int64_t steps_per_epoch);

struct PriorConfig {
  FlowOptions model;
  PriorTrainOptions training;
};

// Throws std::invalid_argument naming the field, its value and the rule it broke.
inline void ValidatePriorConfig(const PriorConfig& c) {
  auto bad = [](const std::string& field, double value, const std::string& rule) {
    std::string v = std::to_string(value);
    throw std::invalid_argument(field + " = " + v + " breaks the rule: " + rule);
  };
  const FlowOptions& m = c.model;
  const PriorTrainOptions& t = c.training;
  if (m.num_layers < 1 || m.num_layers > 64) bad("model.layers", m.num_layers, "must be in 1..64");
  if (m.num_reflections < 0 || m.num_reflections > 4096) {
    bad("model.reflections", m.num_reflections, "must be in 0..4096 (0 = dim)");
  }
  if (!(m.prelu_init > 0) || !std::isfinite(m.prelu_init)) {
    bad("model.prelu_init", m.prelu_init, "must be > 0 (a PReLU slope <= 0 is not invertible)");
  }
  if (t.epochs < 1) bad("training.epochs", t.epochs, "must be >= 1");
  if (t.constant_epochs < 0) bad("training.constant_epochs", t.constant_epochs, "must be >= 0");
  if (t.batch_size < 1) bad("training.batch_size", t.batch_size, "must be >= 1");
  if (!(t.learning_rate > 0) || !std::isfinite(t.learning_rate)) {
    bad("training.learning_rate", t.learning_rate, "must be > 0");
  }
  if (!(t.weight_decay >= 0) || !std::isfinite(t.weight_decay)) {
    bad("training.weight_decay", t.weight_decay, "must be >= 0");
  }
  if (!(t.adam_beta1 >= 0 && t.adam_beta1 < 1))
    bad("training.adam_beta1", t.adam_beta1, "must be in [0, 1)");
  if (!(t.adam_beta2 >= 0 && t.adam_beta2 < 1))
    bad("training.adam_beta2", t.adam_beta2, "must be in [0, 1)");
  if (!(t.adam_eps > 0)) bad("training.adam_eps", t.adam_eps, "must be > 0");
  if (!(t.held_out_share >= 0 && t.held_out_share < 1)) {
    bad("training.held_out_share", t.held_out_share, "must be in [0, 1)");
  }
  if (t.frame_stride < 1) bad("training.frame_stride", t.frame_stride, "must be >= 1");
  if (t.min_steps < 0 || t.min_steps > 10000000)
    bad("training.min_steps", t.min_steps, "must be in 0..10000000");
}

// What training produced, stored in the bundle for users and the model card.
struct PriorTrainingSummary {
  std::string protocol;         // protocol name; "" when not trained on a protocol
  double fps = 0;               // the protocol's frame rate (Hz); 0 = unknown
  int64_t train_frames = 0;     // frames seen per epoch
  int64_t held_out_frames = 0;  // frames of the held-out training clips
  int64_t test_frames = 0;      // frames of the protocol's test split (0 = not evaluated)
  int epochs_completed = 0;
  std::vector<double> train_nll;     // [epochs] mean NLL of the epoch's steps, nats per pose
  std::vector<double> held_out_nll;  // [epochs] NLL of the held-out clips after each epoch, nats
  double test_nll = std::numeric_limits<double>::quiet_NaN();  // mean over the test split, nats
  // Quantiles of the held-out frames' NLL (nats) after training: what real poses score. A frame
  // scoring above held_out_nll_q99 is less likely than 99% of real held-out poses.
  double held_out_nll_q50 = std::numeric_limits<double>::quiet_NaN();
  double held_out_nll_q90 = std::numeric_limits<double>::quiet_NaN();
  double held_out_nll_q99 = std::numeric_limits<double>::quiet_NaN();
  double seconds = 0;  // training wall time over every run (resumes included)
  int threads = 0;     // LibTorch/BLAS threads
};

// One stored parameter tensor (in weights.npy, concatenated in this order).
struct PriorParameterEntry {
  std::string name;            // "layers.0.reflections", ...
  std::vector<int64_t> shape;  // e.g. {48, 48}
};

// A saved prior: prior.yaml (this) + weights.npy (float32 [P], the parameters concatenated).
// The config as YAML text (`model:` and `training:` mappings, every key, doubles with 17 digits):
// prior.yaml embeds it and training checkpoints compare it (bundle/prior_bundle.h parses it back).
std::string FormatFlowConfig(const PriorConfig& config);
// A double as that text writes it: 17 significant digits, .nan, .inf, -.inf.
std::string FlowNumberText(double v);

struct PriorManifest {
  static constexpr const char* kFormat = "motionfork-flow-prior";
  static constexpr int kVersion = 1;
  int version = kVersion;
  // Skeleton: joints root first, each parent before its children; parent -1 for the root.
  std::string skeleton_name;
  std::string skeleton_config;  // config it came from ("bandai"); "" = unknown
  std::vector<std::string> joint_names;
  std::vector<int> parents;
  std::vector<double> bone_lengths;  // [J-1] metres, mean of the training frames
  int dim = 0;                       // 3 * (J - 1)
  PriorConfig config;
  PriorTrainingSummary summary;
  std::string weights_file = "weights.npy";
  std::string weights_checksum;  // "fnv1a64:<16 hex digits>" of the .npy bytes
  std::vector<PriorParameterEntry> parameters;
};

}  // namespace motionfork
