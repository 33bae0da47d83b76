// Predictor: what `motionfork eval` evaluates. Given a history, return K futures.
//
// The baselines (eval/baselines.h) implement it; a trained generator implements it the same way
// and links motionfork_eval (this module does not depend on any model code). The evaluation job
// (eval/evaluate.h) checks a predictor's skeleton and window lengths against the protocol before
// the first call, so a model trained for another skeleton fails with a clear message.
//
// Frames and units: positions in metres on the protocol skeleton (root first, parents before
// children), at the protocol frame rate. The history is given in world coordinates, as recorded;
// futures are returned in the same frame. The protocol's metrics only see root-relative poses, so
// a predictor that models poses alone may put the root anywhere (e.g. at the last observed root).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

struct PredictRequest {
  int num_samples = 50;  // K >= 1
  // Same history, request and seed -> same futures. Deterministic predictors ignore it.
  uint64_t seed = 0;
  // The controllable setting: index of a part of skeleton().GetPartition() (the default
  // partition) whose motion every sample shares, or -1 for none. Only predictors whose
  // SupportsFixedPart() is true accept it.
  int fixed_part = -1;
};

class Predictor {
 public:
  virtual ~Predictor() = default;

  // Short name for tables and JSON: "zero-velocity", "nearest-neighbours", a model's name.
  virtual std::string name() const = 0;
  // One line on what it is (training windows used, bundle path, ...); may be empty.
  virtual std::string description() const { return ""; }
  // Identity of learned parameters (the model bundle's hash); empty for non-learned predictors.
  virtual std::string bundle_hash() const { return ""; }

  // The skeleton, history and future lengths (frames) the predictor works on.
  virtual const Skeleton& skeleton() const = 0;
  virtual int t_his() const = 0;
  virtual int t_pred() const = 0;
  virtual bool SupportsFixedPart() const { return false; }

  // history: [t_his, J, 3] metres. futures: resized to [K, t_pred, J, 3] metres.
  // Throws std::invalid_argument for a wrong history size, K < 1, a fixed part out of range, or a
  // fixed part the predictor does not support.
  void Predict(const std::vector<float>& history, const PredictRequest& request,
               std::vector<float>* futures);

 protected:
  // Called by Predict with validated arguments. futures: [K, t_pred, J, 3], caller-owned,
  // contents undefined on entry. Evaluate with several threads calls it from all of them at once:
  // it must not change the predictor (the baselines and the generator's adapter do not).
  virtual void DoPredict(const float* history, const PredictRequest& request, float* futures) = 0;
};

}  // namespace motionfork
