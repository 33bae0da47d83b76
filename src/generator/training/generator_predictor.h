// A trained generator as an evaluation Predictor (eval/predictor.h), so `motionfork eval --model`
// scores it exactly like the baselines.
#pragma once

#include <string>

#include "eval/predictor.h"
#include "generator/inference/forecaster.h"

namespace motionfork {

class GeneratorPredictor : public Predictor {
 public:
  // bundle_hash: identity of the weights (e.g. a hash of generator.pt) for reports. repair: the
  // forecaster's angle-range repair (ForecastRequest::repair).
  GeneratorPredictor(Forecaster forecaster, std::string name, std::string bundle_hash,
                     bool repair = true);

  std::string name() const override { return name_; }
  std::string description() const override;
  std::string bundle_hash() const override { return hash_; }
  const Skeleton& skeleton() const override { return *forecaster_.skeleton(); }
  int t_his() const override { return forecaster_.config().generator.t_his; }
  int t_pred() const override { return forecaster_.config().generator.t_pred; }
  bool SupportsFixedPart() const override { return true; }

 protected:
  // Futures keep the root at the history's last root position (the model predicts poses).
  void DoPredict(const float* history, const PredictRequest& request, float* futures) override;

 private:
  Forecaster forecaster_;
  std::string name_, hash_;
  bool repair_ = true;
};

// A short hash of a bundle's weights file (FNV-1a 64 of generator.pt, hex).
std::string GeneratorBundleHash(const std::string& bundle_dir);

}  // namespace motionfork
