#include "generator/model/gcn.h"

#include <cmath>

#include "generator/model/bf16_matmul.h"
#include "generator/model/fused_ops.h"

namespace motionfork {

GraphConvImpl::GraphConvImpl(int64_t nodes, int64_t in_features, int64_t out_features,
                             int64_t shared_features) {
  // GSPS initialisation: uniform(-1/sqrt(out), 1/sqrt(out)) for every parameter.
  const double stdv = 1.0 / std::sqrt(static_cast<double>(out_features));
  weight =
      register_parameter("weight", torch::empty({in_features, out_features}).uniform_(-stdv, stdv));
  if (shared_features > 0) {
    shared_weight = register_parameter(
        "shared_weight", torch::empty({shared_features, out_features}).uniform_(-stdv, stdv));
  }
  adjacency = register_parameter("adjacency", torch::empty({nodes, nodes}).uniform_(-stdv, stdv));
  bias = register_parameter("bias", torch::empty({out_features}).uniform_(-stdv, stdv));
}

torch::Tensor GraphConvImpl::forward(const torch::Tensor& x, const torch::Tensor& z) {
  return Mix(x, z) + bias;
}

torch::Tensor GraphConvImpl::Mix(const torch::Tensor& x, const torch::Tensor& z) {
  const int64_t N = x.size(0), B = x.size(1), out = weight.size(1);
  const torch::Tensor rows = x.reshape({N * B, x.size(2)});
  torch::Tensor support =
      (bf16_products ? Bf16MatMul(rows, weight) : rows.mm(weight)).view({N, B, out});
  // In place: the product's backward pass does not need its result.
  if (z.defined()) support.add_(z.mm(shared_weight).unsqueeze(0));
  // The node mix A x over node-major rows: one product of [N, N] and [N, B * out].
  return adjacency.mm(support.view({N, -1})).view({N, B, out});
}

NodeBatchNormImpl::NodeBatchNormImpl(int64_t nodes, int64_t features, double momentum_, double eps_)
    : momentum(momentum_), eps(eps_) {
  gamma = register_parameter("gamma", torch::ones({nodes, 1, features}));
  beta = register_parameter("beta", torch::zeros({nodes, 1, features}));
  running_mean = register_buffer("running_mean", torch::zeros({nodes, 1, features}));
  running_var = register_buffer("running_var", torch::ones({nodes, 1, features}));
}

torch::Tensor NodeBatchNormImpl::forward(const torch::Tensor& x) {
  if (is_training() && x.size(1) > 1) {
    const torch::Tensor mean = x.mean(1, /*keepdim=*/true);
    const torch::Tensor var = (x - mean).pow(2).mean(1, /*keepdim=*/true);
    {
      torch::NoGradGuard no_grad;
      const double n = static_cast<double>(x.size(1));
      running_mean.mul_(1 - momentum).add_(momentum * mean.detach());
      running_var.mul_(1 - momentum).add_(momentum * var.detach() * (n / (n - 1)));
    }
    return (x - mean) * torch::rsqrt(var + eps) * gamma + beta;
  }
  // Inference: one fused scale and shift per (node, feature).
  const torch::Tensor scale = gamma * torch::rsqrt(running_var + eps);
  return torch::addcmul(beta - running_mean * scale, x, scale);
}

GraphLayerImpl::GraphLayerImpl(int64_t nodes, int64_t in, int64_t out, int64_t shared,
                               bool batch_norm, double dropout_)
    : dropout(dropout_) {
  conv = register_module("conv", GraphConv(nodes, in, out, shared));
  if (batch_norm) norm = register_module("norm", NodeBatchNorm(nodes, out));
}

torch::Tensor GraphLayerImpl::forward(const torch::Tensor& x, const torch::Tensor& z,
                                      int64_t copies) {
  torch::Tensor y;
  double n = static_cast<double>(x.size(1) * copies);  // samples the batch stands for
  if (!norm) {
    y = FusedTanh(conv->forward(x, z));
  } else if (is_training() && (n > 1 || sync)) {
    // The conv's bias goes to the batch norm, which cancels it (it is never added).
    torch::Tensor mean, var;
    double rows = 0;  // the whole batch's, over the workers
    y = BatchNormTanh(conv->Mix(x, z), norm->gamma, norm->beta, norm->eps, &mean, &var, conv->bias,
                      sync, &rows);
    n = rows * static_cast<double>(copies);
    torch::NoGradGuard no_grad;
    norm->running_mean.mul_(1 - norm->momentum).add_(norm->momentum * mean);
    norm->running_var.mul_(1 - norm->momentum).add_(norm->momentum * var * (n / (n - 1)));
  } else if (!torch::GradMode::is_enabled()) {
    y = conv->forward(x, z);
    const torch::Tensor scale = norm->gamma * torch::rsqrt(norm->running_var + norm->eps);
    y = ScaleShiftTanh(y, scale, norm->beta - norm->running_mean * scale);
  } else {
    y = FusedTanh(norm->forward(conv->forward(x, z)));
  }
  if (dropout > 0 && is_training()) y = torch::dropout(y, dropout, /*train=*/true);
  return y;
}

ResidualBlockImpl::ResidualBlockImpl(int64_t nodes, int64_t features, bool batch_norm,
                                     double dropout) {
  first = register_module("first", GraphLayer(nodes, features, features, 0, batch_norm, dropout));
  second = register_module("second", GraphLayer(nodes, features, features, 0, batch_norm, dropout));
}

torch::Tensor ResidualBlockImpl::forward(const torch::Tensor& x, int64_t copies) {
  return second->forward(first->forward(x, {}, copies), {}, copies) + x;
}

PartNetworkImpl::PartNetworkImpl(int64_t nodes, int64_t coeff_features, int64_t hidden,
                                 int64_t num_blocks, int64_t nz, bool batch_norm, double dropout) {
  input =
      register_module("input", GraphLayer(nodes, coeff_features, hidden, nz, batch_norm, dropout));
  blocks = register_module("blocks", torch::nn::ModuleList());
  for (int64_t i = 0; i < num_blocks; ++i) {
    blocks->push_back(ResidualBlock(nodes, hidden, batch_norm, dropout));
  }
  output = register_module("output", GraphConv(nodes, hidden, coeff_features, 0));
}

torch::Tensor PartNetworkImpl::forward(const torch::Tensor& coeffs, const torch::Tensor& z,
                                       int64_t copies) {
  torch::Tensor y = input->forward(coeffs, z, copies);
  for (const auto& block : *blocks) y = block->as<ResidualBlock>()->forward(y, copies);
  return output->forward(y) + coeffs;
}

}  // namespace motionfork
