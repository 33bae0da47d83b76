// Forecaster: a saved generator bundle, loaded, turning histories into K futures. No LibTorch in
// this header: apps, the evaluation and embedding programs use it as plain C++.
//
// Bundle (a folder): model.yaml (protocol, sizes, skeleton with parts; see config/model_config.h)
// and generator.pt (LibTorch weights and batch-norm statistics); optionally constraints.yaml (the
// angle ranges predictions are repaired to) and prior/ (the pose prior, for validity figures).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bodyparts/part_plan.h"
#include "config/model_config.h"
#include "core/motion.h"

namespace motionfork {

struct ForecastRequest {
  int k = 50;                            // futures per history
  uint64_t seed = 0;                     // same seed, same futures
  std::vector<std::string> fixed_parts;  // parts whose latent is shared by all K futures
  // Move predicted poses that break the bundle's angle ranges (constraints.yaml, when it has one)
  // back inside them, as little as it takes (generator/pose_repair.h). false: the raw network
  // output.
  bool repair = true;
};

struct Forecast {
  int k = 0, t_his = 0, t_pred = 0, joints = 0;
  double fps = 0;
  std::vector<float> history;  // [t_his, J, 3] the input frames, metres
  // [K, t_pred, J, 3] metres; the model predicts root-relative poses, placed here at the last
  // history frame's root position.
  std::vector<float> futures;
};

class Forecaster {
 public:
  // Throws FormatError naming the missing or malformed file. Predictions run the fused generator
  // (inference/fused_generator.h, any CPU); with $MOTIONFORK_FAST_GENERATOR=0 at load time they
  // run the LibTorch network instead (for comparisons; same futures within 1e-5 m).
  static Forecaster Load(const std::string& bundle_dir);
  ~Forecaster();
  Forecaster(Forecaster&&) noexcept;
  Forecaster& operator=(Forecaster&&) noexcept;

  const ModelConfig& config() const;
  const std::shared_ptr<const Skeleton>& skeleton() const;
  const PartPlan& parts() const;
  // True when the bundle carries constraints.yaml, so predictions can be repaired to its ranges.
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
  // the root held at the history's last root position. No skeleton or frame-rate checks: callers
  // (Predict, the evaluation's Predictor) have done them.
  std::vector<float> PredictWorld(const float* history, const ForecastRequest& request) const;

  // Saves a bundle (model.yaml + generator.pt) from a trained network; used by training.
  struct Impl;

 private:
  explicit Forecaster(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace motionfork
