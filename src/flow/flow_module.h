// The pose prior's network in LibTorch: a normalizing flow on limb directions (GSPS).
//
// Row-vector convention, x [B, D] with D = 3 (J - 1) (48 for 17 joints). Layer l maps
//   y = x W_l + b_l,  W_l = Q_l R_l,
// Q_l orthogonal (a product of Householder reflections), R_l upper-triangular with a positive
// diagonal exp(rho_l); every layer but the last is followed by a PReLU with slope exp(alpha_l).
//   log p(x) = log N(z; 0, I) + sum_l sum_i rho_l,i + sum_l alpha_l * #(negative PReLU inputs).
//
// Speed: Q_l depends only on the parameters, so every call builds each W_l once as a D x D matrix
// (the reflections accumulated in compact WY form: Q = I - U T^-1 U^T, one triangular solve, in
// float64) and applies it to the batch as one matrix product. The original code applied each of
// the D reflections to every pose.
//
// Use this header for training and for differentiable use inside other networks (gradients flow
// to the poses and, unless frozen, to the parameters). PosePrior (pose_prior.h) wraps it for
// callers without LibTorch.
#pragma once

#include <torch/torch.h>

#include <utility>
#include <vector>

#include "flow/flow_options.h"

namespace motionfork {

// One invertible linear layer x -> x Q R + b.
class InvertibleLinearImpl : public torch::nn::Module {
 public:
  // dim: D; num_reflections: Householder vectors making Q (1..D). Parameters are left
  // uninitialised (zero): PoseFlowImpl::Initialize fills them.
  InvertibleLinearImpl(int dim, int num_reflections);

  // Q: [D, D] float64, exactly orthogonal up to rounding (Q^T Q = I to ~1e-14).
  torch::Tensor Orthogonal() const;
  // Q by applying the reflections one after another (the original code's way). For tests.
  torch::Tensor OrthogonalSequential() const;
  // R: [D, D] float64, upper-triangular, diagonal exp(rho).
  torch::Tensor Triangular() const;
  // W = Q R and W^-1 = R^-1 Q^T: [D, D] float64.
  torch::Tensor Weight() const;
  torch::Tensor InverseWeight() const;
  // sum_i rho_i = log |det W| (a 0-d tensor, float64).
  torch::Tensor LogAbsDet() const;

  int dim() const { return dim_; }
  int num_reflections() const { return num_reflections_; }

  torch::Tensor reflections;  // [K, D] Householder vectors (rows; their length does not matter)
  torch::Tensor r_log_diag;   // [D] rho: log of R's diagonal
  torch::Tensor r_upper;      // [D (D - 1) / 2] R's strict upper triangle, row by row
  torch::Tensor bias;         // [D] b

 private:
  int dim_;
  int num_reflections_;
  torch::Tensor upper_rows_, upper_cols_;  // int64 indices of the strict upper triangle
};
TORCH_MODULE(InvertibleLinear);

class PoseFlowImpl : public torch::nn::Module {
 public:
  // dim: D = 3 (J - 1). Throws std::invalid_argument for a bad option (see ValidatePriorConfig).
  PoseFlowImpl(int dim, const FlowOptions& options);

  // Deterministic initialisation for a seed (independent of LibTorch's global generator), like
  // the original's PyTorch defaults: reflections ~ N(0, 1); rho, R's strict upper part and b
  // ~ U(-1/sqrt(D), 1/sqrt(D)); PReLU slope = options.prelu_init.
  void Initialize(uint64_t seed);

  // x: [B, D] -> (z [B, D], log |det dz/dx| [B]), in x's dtype.
  std::pair<torch::Tensor, torch::Tensor> forward(const torch::Tensor& x) const;
  // z: [B, D] -> x [B, D] (exact inverse of forward).
  torch::Tensor inverse(const torch::Tensor& z) const;
  // x: [B, D] -> log p(x) [B], nats (density on R^D; the standard normal base included).
  // With every parameter frozen (requires_grad false) and x requiring grad, a fused path keeps
  // only z and the PReLU masks for backward (first-order gradients only).
  torch::Tensor log_prob(const torch::Tensor& x) const;

  int dim() const { return dim_; }
  int num_layers() const { return static_cast<int>(layers_.size()); }
  const FlowOptions& options() const { return options_; }
  const InvertibleLinear& layer(int l) const { return layers_.at(l); }
  // log of layer l's PReLU slope (l < num_layers - 1).
  const torch::Tensor& prelu_log_slope(int l) const { return prelu_log_slopes_.at(l); }

  // Every parameter in a fixed order (names as in named_parameters()): the saved layout.
  std::vector<std::pair<std::string, torch::Tensor>> OrderedParameters() const;
  int64_t NumParameters() const;
  bool AnyParameterRequiresGrad() const;
  // No parameter requires grad any more, and eval mode: the prior as a fixed loss term (log_prob
  // then takes the fused path when its input requires grad).
  void Freeze();

  // One forward sweep: z, log-det and each PReLU's mask of negative inputs ([B, D] bool).
  struct Pass {
    torch::Tensor z, log_det;
    std::vector<torch::Tensor> negative;
  };
  Pass Run(const torch::Tensor& x) const;

 private:
  void CheckInput(const torch::Tensor& x, const char* what) const;

  int dim_;
  FlowOptions options_;
  std::vector<InvertibleLinear> layers_;
  std::vector<torch::Tensor> prelu_log_slopes_;  // [1] each
};
TORCH_MODULE(PoseFlow);

// Differentiable limb directions: positions [..., J, 3] (metres) -> unit directions
// [..., 3 (J - 1)] ((joint - parent) / sqrt(|joint - parent|^2 + eps^2), limb k ends at joint
// k + 1), for scoring predicted poses with the prior inside a training graph. parents: the
// skeleton's (parents[0] = -1, parents[j] < j). A collapsed bone gives a zero direction and finite
// gradients. CPU float/double tensors take one fused pass each way (first-order gradients only);
// others go through tensor ops (LimbDirectionsReference).
torch::Tensor LimbDirections(const torch::Tensor& positions, const std::vector<int>& parents,
                             double eps = 1e-8);
// The same for root-relative poses that omit the root (the generator's layout): poses
// [..., J - 1, 3], joint j at index j - 1, the root at the origin. Scoring predicted poses with a
// frozen prior inside a training step:
//   prior.module()->Freeze();
//   nll = -prior.module()->log_prob(LimbDirectionsRootRelative(poses.reshape({-1, J - 1, 3}),
//                                                              parents)).mean();
torch::Tensor LimbDirectionsRootRelative(const torch::Tensor& poses,
                                         const std::vector<int>& parents, double eps = 1e-8);
torch::Tensor LimbDirectionsReference(const torch::Tensor& positions,
                                      const std::vector<int>& parents, double eps = 1e-8);

}  // namespace motionfork
