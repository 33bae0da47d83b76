// Forecaster: a generator network turning histories into K futures. No LibTorch in this header:
// apps, the evaluation and embedding programs use it as plain C++. A saved bundle (model.yaml,
// generator.pt, optionally constraints.yaml) loads as one through LoadForecaster
// (bundle/generator_bundle.h).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bodyparts/part_plan.h"
#include "constraints/constraint_spec.h"
#include "core/heading.h"
#include "core/motion.h"
#include "generator/kernels/precision.h"
#include "generator/model/generator_options.h"

namespace motionfork {

class GeneratorNetImpl;   // generator/model/generator_net.h (LibTorch)
class TrajectoryNetImpl;  // generator/trajectory/trajectory_net.h (LibTorch)

// Futures per history at most: every future is kept in memory (with its pose checks, ~12 KB each
// for the Bandai model), so K is bounded before anything is allocated.
constexpr int kMaxFutures = 10000;

struct ForecastRequest {
  int k = 50;                            // futures per history, 1..kMaxFutures
  uint64_t seed = 0;                     // same seed, same futures
  std::vector<std::string> fixed_parts;  // parts whose latent is shared by all K futures
  // Move predicted poses that break the angle ranges (the bundle's constraints.yaml, when it has
  // one) back inside them, as little as it takes (generator/pose_repair.h). false: the raw network
  // output.
  bool repair = true;
};

// Throws std::invalid_argument "expected 1..10000 futures per history (k), got K" for k outside
// 1..kMaxFutures.
void ValidateForecastRequest(const ForecastRequest& request);

struct Forecast {
  int k = 0, t_his = 0, t_pred = 0, joints = 0;
  double fps = 0;
  std::vector<float> history;  // [t_his, J, 3] the input frames, metres
  // [K, t_pred, J, 3] metres, in the history's frame. With a trajectory network (moves_root) the
  // root moves as each future's trajectory says; without one every future's root stays at the
  // last history frame's root position (the model predicts root-relative poses).
  std::vector<float> futures;
  bool root_moves = false;
};

class Forecaster {
 public:
  // config: what the network is (sizes, skeleton with its parts, frame rate); net: the network
  // (put in eval mode); constraints: the angle ranges predictions are repaired to (none: no
  // repair). Predictions run the fused generator (inference/fused_generator.h) where the AVX-512
  // backend runs; with $MOTIONFORK_FAST_GENERATOR=0 at construction they run the LibTorch network
  // instead (=1: the fused generator on any backend; same futures within 1e-5 m). Throws
  // std::invalid_argument for a null net, a body frame on a skeleton without left/right joints,
  // and what ParseUp, Skeleton::Build, MakePartPlan and ConstraintSet::Build throw.
  Forecaster(ModelConfig config, std::shared_ptr<GeneratorNetImpl> net,
             std::optional<ConstraintSetSpec> constraints = std::nullopt);
  ~Forecaster();
  Forecaster(Forecaster&&) noexcept;
  Forecaster& operator=(Forecaster&&) noexcept;

  const ModelConfig& config() const;
  // The products' arithmetic (precision.h; constructed: fp32). kBf16 runs the fused generator
  // with bf16 products whatever the backend; kAuto resolves for this CPU. Throws what
  // ResolvePrecision throws. Not thread-safe: set it before predicting.
  void SetPrecision(Precision p);
  Precision precision() const;  // as resolved: kFp32 or kBf16
  const std::shared_ptr<const Skeleton>& skeleton() const;
  const PartPlan& parts() const;
  // The up axis of a network that predicts in the body's own frame (GeneratorOptions::body_frame,
  // issue 27): each history is turned about it so that its last frame's heading (core/heading.h:
  // the line between the skeleton's hips) is the same, and its futures are turned back, so that
  // turning a history turns its futures alike. None: the data's axes.
  std::optional<UpAxis> body_frame() const;
  // Where the root goes (issue 27): a trajectory network (bundle's trajectory/) run on each
  // future in the body's frame, so that PredictWorld's futures move. Throws std::invalid_argument
  // when the generator is not in the body's frame, or the network's frames, nodes or up axis
  // differ from the generator's. Not thread-safe: set it before predicting.
  void AttachTrajectory(std::shared_ptr<TrajectoryNetImpl> trajectory);
  bool moves_root() const;
  // True when constructed with constraints (a bundle's constraints.yaml), so predictions can be
  // repaired to their ranges.
  bool repairs() const;

  // history: the model's skeleton (same joint names and parents) at the model's frame rate, at
  // least t_his frames from `start`; frames [start, start + t_his) are used. Throws
  // std::invalid_argument naming what does not match.
  Forecast Predict(const Motion& history, int start, const ForecastRequest& request) const;

  // Batched, root-relative without the root (what the metrics use): histories
  // [Bh, t_his, J-1, 3] -> futures [Bh, K, t_pred, J-1, 3], metres.
  std::vector<float> PredictRootRelative(const std::vector<float>& histories, int num_histories,
                                         const ForecastRequest& request) const;

  // One history in world coordinates, [t_his, J, 3] metres -> futures [K, t_pred, J, 3] metres,
  // the root moving when moves_root(), else held at the history's last root position. No skeleton
  // or frame-rate checks: callers (Predict, the evaluation's Predictor) have done them.
  std::vector<float> PredictWorld(const float* history, const ForecastRequest& request) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace motionfork
