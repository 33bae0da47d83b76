// Graph-convolutional building blocks of the GSPS generator (LibTorch).
//
// Layout: node-major [N, B, F] (N graph nodes, B samples, F features), so that X W is one
// [N*B, F] x [F, H] matrix product and A (X W) is one [N, N] x [N, B*H] product: no permutes, no
// batched small products.
#pragma once

#include <torch/torch.h>

namespace motionfork {

struct BatchSync;  // model/fused_ops.h

// Y = A (X W) + b with a learned dense adjacency A [N, N] (not the skeleton graph).
// Optionally a second input z [B, Z] shared by all nodes: Y = A (X Wx + z Wz) + b, which equals
// concatenating z to every node's features, without building the concatenation.
class GraphConvImpl : public torch::nn::Module {
 public:
  GraphConvImpl(int64_t nodes, int64_t in_features, int64_t out_features,
                int64_t shared_features = 0);
  // x: [N, B, in]; z: [B, shared] or undefined. Returns [N, B, out].
  torch::Tensor forward(const torch::Tensor& x, const torch::Tensor& z = {});
  // A (X W [+ z Wz]) without the bias (for a batch norm that takes the bias itself).
  torch::Tensor Mix(const torch::Tensor& x, const torch::Tensor& z = {});

  torch::Tensor weight, shared_weight, adjacency, bias;
  // X W with bfloat16 inputs and float32 sums (model/bf16_matmul.h; training, issue 30).
  bool bf16_products = false;
};
TORCH_MODULE(GraphConv);

// Batch normalisation over samples for each (node, feature), as BatchNorm1d(N * F) on [B, N*F]
// in the GSPS code, for the node-major layout [N, B, F].
class NodeBatchNormImpl : public torch::nn::Module {
 public:
  NodeBatchNormImpl(int64_t nodes, int64_t features, double momentum = 0.1, double eps = 1e-5);
  torch::Tensor forward(const torch::Tensor& x);

  torch::Tensor gamma, beta, running_mean, running_var;
  double momentum, eps;
};
TORCH_MODULE(NodeBatchNorm);

// graph-conv -> [batch norm] -> tanh -> [dropout]
//
// copies (training): each of x's B rows stands for `copies` identical samples (the nested
// training batch computes a part once per distinct input, GeneratorNetImpl::ForwardNested). The
// batch statistics of equal copies are those of the rows, so only the running variance's
// unbiased correction, B * copies / (B * copies - 1), sees the count.
class GraphLayerImpl : public torch::nn::Module {
 public:
  GraphLayerImpl(int64_t nodes, int64_t in, int64_t out, int64_t shared, bool batch_norm,
                 double dropout);
  torch::Tensor forward(const torch::Tensor& x, const torch::Tensor& z = {}, int64_t copies = 1);

  GraphConv conv{nullptr};
  NodeBatchNorm norm{nullptr};
  double dropout;
  // Training: batch statistics over the workers of a data-parallel run (not owned; null: this
  // process's batch alone).
  const BatchSync* sync = nullptr;
};
TORCH_MODULE(GraphLayer);

// Two graph layers plus the block's input (residual).
class ResidualBlockImpl : public torch::nn::Module {
 public:
  ResidualBlockImpl(int64_t nodes, int64_t features, bool batch_norm, double dropout);
  torch::Tensor forward(const torch::Tensor& x, int64_t copies = 1);

  GraphLayer first{nullptr}, second{nullptr};
};
TORCH_MODULE(ResidualBlock);

// One body part's network: graph layer (coefficients + z -> hidden), residual blocks, graph-conv
// (hidden -> coefficients), plus the input coefficients.
class PartNetworkImpl : public torch::nn::Module {
 public:
  PartNetworkImpl(int64_t nodes, int64_t coeff_features, int64_t hidden, int64_t blocks, int64_t nz,
                  bool batch_norm, double dropout);
  // coeffs: [N, B, C]; z: [B, nz]. Returns [N, B, C]. copies: as for GraphLayer.
  torch::Tensor forward(const torch::Tensor& coeffs, const torch::Tensor& z, int64_t copies = 1);

  GraphLayer input{nullptr};
  torch::nn::ModuleList blocks;
  GraphConv output{nullptr};
};
TORCH_MODULE(PartNetwork);

}  // namespace motionfork
