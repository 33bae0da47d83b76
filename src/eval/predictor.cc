#include "eval/predictor.h"

#include <stdexcept>
#include <string>

namespace motionfork {

void Predictor::Predict(const std::vector<float>& history, const PredictRequest& request,
                        std::vector<float>* futures) {
  const int J = skeleton().num_joints();
  const size_t expected = static_cast<size_t>(t_his()) * J * 3;
  if (history.size() != expected) {
    throw std::invalid_argument(name() + ": expected a history of [" + std::to_string(t_his()) +
                                ", " + std::to_string(J) + ", 3] = " + std::to_string(expected) +
                                " values, got " + std::to_string(history.size()));
  }
  if (request.num_samples < 1) {
    throw std::invalid_argument(name() + ": expected num_samples >= 1, got " +
                                std::to_string(request.num_samples));
  }
  if (request.fixed_part != -1) {
    if (!SupportsFixedPart()) {
      throw std::invalid_argument(name() + " cannot fix a body part (controllable prediction)");
    }
    const int parts = static_cast<int>(skeleton().GetPartition().parts.size());
    if (request.fixed_part < 0 || request.fixed_part >= parts) {
      throw std::invalid_argument(name() + ": expected fixed_part -1 or 0.." +
                                  std::to_string(parts - 1) + ", got " +
                                  std::to_string(request.fixed_part));
    }
  }
  futures->resize(static_cast<size_t>(request.num_samples) * t_pred() * J * 3);
  DoPredict(history.data(), request, futures->data());
}

}  // namespace motionfork
