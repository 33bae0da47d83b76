#include "generator/model/generator_net.h"

#include <stdexcept>
#include <string>

#include "core/dct.h"

namespace motionfork {

GeneratorNetImpl::GeneratorNetImpl(const GeneratorOptions& options,
                                   std::vector<std::vector<int64_t>> part_nodes)
    : options_(options), part_nodes_(std::move(part_nodes)) {
  ValidateGeneratorOptions(options_);
  const int64_t N = options_.num_nodes;
  std::vector<int> owner(N, -1);
  for (size_t p = 0; p < part_nodes_.size(); ++p) {
    auto mask = torch::zeros({N, 1, 1}, torch::kBool);
    for (int64_t n : part_nodes_[p]) {
      if (n < 0 || n >= N || owner[n] >= 0) {
        throw std::invalid_argument("generator: part " + std::to_string(p) + " holds node " +
                                    std::to_string(n) + ", expected a free node in 0.." +
                                    std::to_string(N - 1));
      }
      owner[n] = static_cast<int>(p);
      mask[n][0][0] = true;
    }
    masks_.push_back(mask);
    parts_.push_back(
        register_module("part" + std::to_string(p),
                        PartNetwork(N, options_.coeff_features(), options_.hidden, options_.blocks,
                                    options_.nz, options_.batch_norm, options_.dropout)));
  }
  for (int64_t n = 0; n < N; ++n) {
    if (owner[n] < 0) {
      throw std::invalid_argument("generator: node " + std::to_string(n) + " is in no body part");
    }
  }
  const Eigen::MatrixXd d = DctMatrix(options_.num_frames()).topRows(options_.n_pre);
  Eigen::MatrixXf df = d.cast<float>();
  // Eigen is column-major: copy row by row into a row-major tensor.
  dct_ = torch::empty({options_.n_pre, options_.num_frames()});
  for (int l = 0; l < options_.n_pre; ++l)
    for (int t = 0; t < options_.num_frames(); ++t) dct_[l][t] = df(l, t);
  idct_ = dct_;
}

torch::Tensor GeneratorNetImpl::EncodeHistory(const torch::Tensor& history) const {
  const int64_t Bh = history.size(0), N = options_.num_nodes, n = options_.n_pre;
  if (history.dim() != 4 || history.size(1) != options_.t_his || history.size(2) != N ||
      history.size(3) != 3) {
    throw std::invalid_argument("generator: expected history [B, " +
                                std::to_string(options_.t_his) + ", " + std::to_string(N) +
                                ", 3], got " + c10::str(history.sizes()));
  }
  const torch::Tensor last =
      history.select(1, options_.t_his - 1).unsqueeze(1).expand({Bh, options_.t_pred, N, 3});
  const torch::Tensor padded =
      torch::cat({history, last}, 1).reshape({Bh, options_.num_frames(), N * 3});
  const torch::Tensor c = torch::matmul(dct_, padded);  // [Bh, n, N*3]
  return c.view({Bh, n, N, 3}).permute({2, 0, 3, 1}).reshape({N, Bh, 3 * n});
}

torch::Tensor GeneratorNetImpl::RepeatSamples(const torch::Tensor& coeffs, int64_t k) {
  const int64_t N = coeffs.size(0), Bh = coeffs.size(1), C = coeffs.size(2);
  return coeffs.unsqueeze(2).expand({N, Bh, k, C}).reshape({N, Bh * k, C});
}

torch::Tensor GeneratorNetImpl::Decode(const torch::Tensor& coeffs,
                                       const std::vector<torch::Tensor>& z,
                                       const std::vector<bool>& fixed, int64_t k) {
  if (z.size() != parts_.size()) {
    throw std::invalid_argument("generator: expected " + std::to_string(parts_.size()) +
                                " latents (one per part), got " + std::to_string(z.size()));
  }
  torch::Tensor current = coeffs;
  for (size_t p = 0; p < parts_.size(); ++p) {
    const bool is_fixed = p < fixed.size() && fixed[p];
    torch::Tensor out = parts_[p]->forward(current, z[p]);
    if (is_fixed && k > 1) {
      const int64_t N = out.size(0), B = out.size(1), C = out.size(2);
      out = out.view({N, B / k, k, C})
                .select(2, 0)
                .unsqueeze(2)
                .expand({N, B / k, k, C})
                .reshape({N, B, C});
    }
    current = torch::where(masks_[p], out, current);
  }
  return current;
}

void GeneratorNetImpl::set_batch_sync(const BatchSync* sync) {
  for (const auto& module : modules()) {
    if (auto* layer = module->as<GraphLayerImpl>()) layer->sync = sync;
  }
}

void GeneratorNetImpl::set_bf16_products(bool on) {
  for (const auto& module : modules()) {
    if (auto* block = module->as<ResidualBlockImpl>()) {
      block->first->conv->bf16_products = on;
      block->second->conv->bf16_products = on;
    }
  }
}

torch::Tensor GeneratorNetImpl::Frames(const torch::Tensor& coeffs) const {
  const int64_t N = coeffs.size(0), B = coeffs.size(1), n = options_.n_pre;
  // Reorder the (small) coefficients, not the (large) frames: the result is contiguous, which
  // every loss and its backward pass over the [B, T, N, 3] futures depend on for speed.
  const torch::Tensor c = coeffs.view({N, B, 3, n}).permute({1, 3, 0, 2}).reshape({B, n, N * 3});
  return torch::matmul(idct_.t(), c).view({B, options_.num_frames(), N, 3});  // [B, T, N, 3]
}

torch::Tensor GeneratorNetImpl::forward(const torch::Tensor& history,
                                        const std::vector<torch::Tensor>& z,
                                        const std::vector<bool>& fixed) {
  const int64_t Bh = history.size(0);
  if (z.empty() || z[0].size(0) % Bh != 0) {
    throw std::invalid_argument("generator: latents must hold Bh * K rows");
  }
  const int64_t k = z[0].size(0) / Bh;
  return Frames(Decode(RepeatSamples(EncodeHistory(history), k), z, fixed, k));
}

torch::Tensor GeneratorNetImpl::ForwardNested(const torch::Tensor& history,
                                              const std::vector<torch::Tensor>& z,
                                              const std::vector<int64_t>& per_part) {
  if (options_.dropout > 0 && is_training()) return forward(history, z);
  const int64_t Bh = history.size(0);
  int64_t K = 1;
  for (int64_t n : per_part) {
    if (n < 1)
      throw std::invalid_argument("generator: samples per part must be >= 1, got " +
                                  std::to_string(n));
    K *= n;
  }
  if (per_part.size() != parts_.size() || z.size() != parts_.size()) {
    throw std::invalid_argument("generator: expected " + std::to_string(parts_.size()) +
                                " latents and sample counts (one per part), got " +
                                std::to_string(z.size()) + " and " +
                                std::to_string(per_part.size()));
  }
  torch::Tensor current = EncodeHistory(history);  // [N, Bh, C]
  int64_t rows = 1;                                // distinct samples per history so far
  for (size_t p = 0; p < parts_.size(); ++p) {
    rows *= per_part[p];
    const int64_t copies = K / rows;
    if (z[p].dim() != 2 || z[p].size(0) != Bh * K) {
      throw std::invalid_argument("generator: latent " + std::to_string(p) + " must hold " +
                                  std::to_string(Bh * K) + " rows, got " + c10::str(z[p].sizes()));
    }
    const torch::Tensor blocks = z[p].reshape({Bh * rows, copies, z[p].size(1)});
    const torch::Tensor zp = blocks.select(1, 0);
    if (!torch::equal(blocks, zp.unsqueeze(1).expand_as(blocks))) {
      throw std::invalid_argument(
          "generator: latent " + std::to_string(p) +
          " is not nested (each code repeated for the later parts' samples)");
    }
    current = RepeatSamples(current, per_part[p]);
    current = torch::where(masks_[p], parts_[p]->forward(current, zp, copies), current);
  }
  return Frames(current);
}

}  // namespace motionfork
