// The trajectory network (issue 27): a future's root motion from its poses. Everything is in the
// body's frame at the last history frame (core/heading.h): poses root-relative without the root,
// root positions relative to the last history root, metres.
//
// The poses' low DCT coefficients over the whole window (the history, and the future of the
// options' future_nodes; the other nodes hold their last history pose) and the history root's
// steps go through a residual MLP to the DCT coefficients of the root's step per future frame,
// summed into positions: the first future frame continues from the last history root. Inputs
// and outputs are standardised by statistics of the training data kept as buffers.
#pragma once

#include <torch/torch.h>

#include "generator/trajectory/trajectory_options.h"

namespace motionfork {

class TrajectoryNetImpl : public torch::nn::Module {
 public:
  explicit TrajectoryNetImpl(const TrajectoryOptions& options);

  // The network's input: poses [B, T, N, 3] (T = t_his + t_pred), root history [B, t_his, 3]
  // -> [B, input_size].
  torch::Tensor Features(const torch::Tensor& poses, const torch::Tensor& root_history) const;

  // The training targets' coefficients: root positions [B, t_pred, 3] relative to the last
  // history root -> [B, n_out * 3] (the coefficients of their steps; Steps inverts it up to the
  // coefficients dropped).
  torch::Tensor StepCoefficients(const torch::Tensor& root_future) const;

  // Sets the standardisation from training features [M, input_size] and targets [M, n_out * 3].
  void SetStatistics(const torch::Tensor& features, const torch::Tensor& targets);

  // -> root positions [B, t_pred, 3] relative to the last history root.
  torch::Tensor forward(const torch::Tensor& poses, const torch::Tensor& root_history);

  const TrajectoryOptions& options() const { return options_; }

 private:
  TrajectoryOptions options_;
  torch::nn::Linear input_{nullptr}, output_{nullptr};
  std::vector<torch::nn::Linear> hidden_;
  torch::Tensor dct_in_;                                 // [n_in, T]
  torch::Tensor dct_out_;                                // [n_out, t_pred]
  torch::Tensor future_;                                 // [N] bool: nodes read over the future
  torch::Tensor in_mean_, in_std_, out_mean_, out_std_;  // buffers
};
TORCH_MODULE(TrajectoryNet);

}  // namespace motionfork
