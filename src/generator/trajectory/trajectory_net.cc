#include "generator/trajectory/trajectory_net.h"

#include <stdexcept>
#include <string>

#include "core/dct.h"

namespace motionfork {

void ValidateTrajectoryOptions(const TrajectoryOptions& o) {
  auto rule = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("trajectory: " + what);
  };
  rule(o.t_his >= 2, "t_his must be >= 2, got " + std::to_string(o.t_his));
  rule(o.t_pred >= 1, "t_pred must be >= 1, got " + std::to_string(o.t_pred));
  rule(o.num_frames() <= 4096, "t_his + t_pred must be <= 4096");
  rule(o.num_nodes >= 1 && o.num_nodes <= 1000,
       "num_nodes must be in 1..1000, got " + std::to_string(o.num_nodes));
  rule(o.n_in >= 1 && o.n_in <= o.num_frames(),
       "n_in must be in 1..t_his + t_pred, got " + std::to_string(o.n_in));
  rule(o.n_out >= 1 && o.n_out <= o.t_pred,
       "n_out must be in 1..t_pred, got " + std::to_string(o.n_out));
  rule(o.hidden >= 1 && o.hidden <= kMaxTrajectoryWidth, "hidden must be in 1.." +
                                                             std::to_string(kMaxTrajectoryWidth) +
                                                             ", got " + std::to_string(o.hidden));
  rule(o.layers >= 1 && o.layers <= kMaxTrajectoryLayers, "layers must be in 1.." +
                                                              std::to_string(kMaxTrajectoryLayers) +
                                                              ", got " + std::to_string(o.layers));
  rule(static_cast<int64_t>(o.input_size()) * o.hidden <= (int64_t{64} << 20),
       "input_size x hidden must be <= 64M weights");
  for (int64_t n : o.future_nodes) {
    rule(n >= 0 && n < o.num_nodes,
         "future node " + std::to_string(n) + " outside 0.." + std::to_string(o.num_nodes - 1));
  }
}

namespace {

// The first `rows` rows of the orthonormal DCT over `frames` frames, [rows, frames].
torch::Tensor DctRows(int rows, int frames) {
  const Eigen::MatrixXd d = DctMatrix(frames);
  torch::Tensor out = torch::empty({rows, frames});
  for (int l = 0; l < rows; ++l)
    for (int t = 0; t < frames; ++t) out[l][t] = static_cast<float>(d(l, t));
  return out;
}

}  // namespace

TrajectoryNetImpl::TrajectoryNetImpl(const TrajectoryOptions& options) : options_(options) {
  ValidateTrajectoryOptions(options_);
  const int64_t in = options_.input_size(), out = options_.n_out * 3, h = options_.hidden;
  input_ = register_module("input", torch::nn::Linear(in, h));
  for (int l = 1; l < options_.layers; ++l)
    hidden_.push_back(register_module("hidden" + std::to_string(l), torch::nn::Linear(h, h)));
  output_ = register_module("output", torch::nn::Linear(h, out));
  // The last layer starts at zero: an untrained network predicts the training data's mean.
  torch::NoGradGuard no_grad;
  output_->weight.zero_();
  output_->bias.zero_();
  dct_in_ = register_buffer("dct_in", DctRows(options_.n_in, options_.num_frames()));
  dct_out_ = register_buffer("dct_out", DctRows(options_.n_out, options_.t_pred));
  torch::Tensor future = torch::zeros({options_.num_nodes}, torch::kBool);
  for (int64_t n : options_.future_nodes) future[n] = true;
  future_ = register_buffer("future_nodes", future);
  in_mean_ = register_buffer("in_mean", torch::zeros({in}));
  in_std_ = register_buffer("in_std", torch::ones({in}));
  out_mean_ = register_buffer("out_mean", torch::zeros({out}));
  out_std_ = register_buffer("out_std", torch::ones({out}));
}

torch::Tensor TrajectoryNetImpl::Features(const torch::Tensor& poses,
                                          const torch::Tensor& root_history) const {
  const int64_t B = poses.size(0), T = options_.num_frames(), N = options_.num_nodes;
  const int64_t th = options_.t_his;
  if (poses.dim() != 4 || poses.size(1) != T || poses.size(2) != N || poses.size(3) != 3 ||
      root_history.dim() != 3 || root_history.size(0) != B || root_history.size(1) != th ||
      root_history.size(2) != 3) {
    throw std::invalid_argument("trajectory: expected poses [B, " + std::to_string(T) + ", " +
                                std::to_string(N) + ", 3] and root history [B, " +
                                std::to_string(th) + ", 3], got " + c10::str(poses.sizes()) +
                                " and " + c10::str(root_history.sizes()));
  }
  // The nodes not read over the future hold their last history pose.
  const torch::Tensor held = poses.select(1, th - 1).unsqueeze(1).expand({B, T - th, N, 3});
  const torch::Tensor future = torch::where(future_.view({1, 1, N, 1}), poses.slice(1, th), held);
  const torch::Tensor window =
      torch::cat({poses.slice(1, 0, th), future}, 1).reshape({B, T, N * 3});
  const torch::Tensor coeffs = torch::matmul(dct_in_, window).reshape({B, -1});
  const torch::Tensor steps =
      (root_history.slice(1, 1) - root_history.slice(1, 0, th - 1)).reshape({B, -1});
  return torch::cat({coeffs, steps}, 1);
}

torch::Tensor TrajectoryNetImpl::StepCoefficients(const torch::Tensor& root_future) const {
  const int64_t B = root_future.size(0);
  const torch::Tensor previous =
      torch::cat({torch::zeros({B, 1, 3}, root_future.options()), root_future.slice(1, 0, -1)}, 1);
  return torch::matmul(dct_out_, root_future - previous).reshape({B, -1});
}

void TrajectoryNetImpl::SetStatistics(const torch::Tensor& features, const torch::Tensor& targets) {
  torch::NoGradGuard no_grad;
  in_mean_.copy_(features.mean(0));
  in_std_.copy_(features.std(0).clamp_min(1e-6));
  out_mean_.copy_(targets.mean(0));
  out_std_.copy_(targets.std(0).clamp_min(1e-6));
}

torch::Tensor TrajectoryNetImpl::forward(const torch::Tensor& poses,
                                         const torch::Tensor& root_history) {
  const int64_t B = poses.size(0);
  torch::Tensor x = (Features(poses, root_history) - in_mean_) / in_std_;
  x = torch::tanh(input_->forward(x));
  for (auto& layer : hidden_) x = x + torch::tanh(layer->forward(x));
  const torch::Tensor coeffs = (output_->forward(x) * out_std_ + out_mean_).view({B, -1, 3});
  const torch::Tensor steps = torch::matmul(dct_out_.t(), coeffs);  // [B, t_pred, 3]
  return steps.cumsum(1);
}

}  // namespace motionfork
