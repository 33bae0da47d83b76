// The GSPS generator as a LibTorch module: DCT of the padded history, one residual graph-conv
// network per body part run in sequence (each overwrites only its own joints and has its own
// latent), inverse DCT back to frames.
//
// Poses are root-relative without the root: N = J - 1 nodes, metres.
#pragma once

#include <torch/torch.h>

#include <vector>

#include "generator/model/gcn.h"
#include "generator/model/generator_options.h"

namespace motionfork {

class GeneratorNetImpl : public torch::nn::Module {
 public:
  // part_nodes: node indices (0..N-1) of each part, in prediction order; disjoint, covering all.
  GeneratorNetImpl(const GeneratorOptions& options, std::vector<std::vector<int64_t>> part_nodes);

  // history: [Bh, t_his, N, 3] -> DCT coefficients of the history padded with its last frame to
  // t_his + t_pred frames, first n_pre kept: [N, Bh, 3 * n_pre] (per node: x, y, z blocks).
  torch::Tensor EncodeHistory(const torch::Tensor& history) const;

  // [N, Bh, C] -> [N, Bh * K, C]; sample b = h * K + k.
  static torch::Tensor RepeatSamples(const torch::Tensor& coeffs, int64_t k);

  // Runs the parts in order on coefficients [N, B, C] with one latent per part, z[p]: [B, nz].
  // fixed (empty = none): parts whose latent all K samples of a history share (B = Bh * K). A
  // fixed part's output is taken from the history's first sample and given to all K: after a
  // varying part its input differs per sample (the graph as the earlier parts left it), and even
  // with equal inputs matrix products may round rows differently by their place in the batch
  // (OpenBLAS's Haswell kernels do, by about 1e-7). The fixed part is then bit-identical across
  // samples, as control promises.
  torch::Tensor Decode(const torch::Tensor& coeffs, const std::vector<torch::Tensor>& z,
                       const std::vector<bool>& fixed = {}, int64_t k = 1);

  // Coefficients [N, B, C] -> frames [B, t_his + t_pred, N, 3].
  torch::Tensor Frames(const torch::Tensor& coeffs) const;

  // history [Bh, t_his, N, 3], z[p]: [Bh * K, nz] -> [Bh * K, t_his + t_pred, N, 3]. fixed: as
  // for Decode.
  torch::Tensor forward(const torch::Tensor& history, const std::vector<torch::Tensor>& z,
                        const std::vector<bool>& fixed = {});

  // Training on nested latents (NestedLatents: z[p] depends on the codes of parts 0..p only), the
  // same futures as forward(history, z) with less arithmetic: part p runs once per distinct input,
  // Bh * per_part[0] * ... * per_part[p] rows instead of Bh * K, and its output is repeated for
  // the later parts' samples (the gradient sums the repeats). Batch statistics are unchanged
  // (every row is repeated equally often). With dropout the repeats would draw different masks:
  // then it runs forward(history, z). Throws if z is not nested as per_part says.
  torch::Tensor ForwardNested(const torch::Tensor& history, const std::vector<torch::Tensor>& z,
                              const std::vector<int64_t>& per_part);

  // Training: every batch-normalised layer takes its statistics over the workers of a
  // data-parallel run (synchronised batch norm, model/fused_ops.h); null: this process's batch
  // alone. Not owned: it must outlive the training.
  void set_batch_sync(const BatchSync* sync);

  // Training with bf16 products (issue 30, training.precision): the H x H products of every
  // residual block (forward and backward) take bfloat16 inputs and keep float32 sums
  // (model/bf16_matmul.h); false: float32 throughout. The input and output layers stay float32.
  void set_bf16_products(bool on);

  const GeneratorOptions& options() const { return options_; }
  int64_t num_parts() const { return static_cast<int64_t>(parts_.size()); }
  const std::vector<std::vector<int64_t>>& part_nodes() const { return part_nodes_; }
  const PartNetwork& part(int64_t p) const { return parts_[p]; }

 private:
  GeneratorOptions options_;
  std::vector<std::vector<int64_t>> part_nodes_;
  std::vector<PartNetwork> parts_;
  std::vector<torch::Tensor> masks_;  // [N, 1, 1] bool per part
  torch::Tensor dct_;                 // [n_pre, T]
  torch::Tensor idct_;  // [n_pre, T] (rows of the orthonormal DCT: its transpose inverts)
};
TORCH_MODULE(GeneratorNet);

}  // namespace motionfork
