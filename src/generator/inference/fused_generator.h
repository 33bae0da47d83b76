// The generator's inference path without LibTorch's per-operation cost: the trained network's
// weights copied once (batch norm folded into a scale and shift per node and feature, weight
// matrices packed) and run by the fused kernels of kernels/panel_product.h (AVX-512 or portable
// backend, chosen per call: kernels/backend.h), so it runs on any CPU. Same futures as
// GeneratorNet::forward in eval mode up to float rounding (a test holds them within 1e-5 m on
// both backends).
//
// Work that does not depend on the latent is done once per history: the history's DCT, and the
// first part's input product X W_x (the latent's share z W_z is one row per sample, added to
// every node through the adjacency's row sums). A fixed part is computed once per history.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace motionfork {

class GeneratorNetImpl;

// The inputs of the hidden layers' products (H x H, nearly all of the work): float32, or, with
// kBf16, bfloat16 with float32 sums in the later half of each part's hidden layers
// (kernels/bf16_product.h: the AVX512-BF16 kernel where the CPU has it, a slow portable one
// elsewhere). The earlier half stays float32: a rounding there passes through every later layer,
// and with all hidden layers in bf16 the shipped Bandai model's worst future moved 1.21 mm from
// float32's on validation windows (every 10th training clip), with the later half 0.77 mm
// (bench/bf16_layer_mask.cc), for 1.64x and 1.31x float32's speed. The input and output layers,
// the latent's product and the inverse DCT stay float32 (small; the output layer in bf16 had
// doubled the futures' deviation), as do batch norm, tanh and the DCT.
enum class ProductPrecision { kFp32, kBf16 };

class FusedGenerator {
 public:
  // Copies the network's eval-mode weights; the network may change or go afterwards.
  // bf16_layers: with kBf16, which hidden layers (part 0's in order, then part 1's, ...) run in
  // bf16 instead of the later half of each part's (for experiments: bench/bf16_layer_mask.cc).
  explicit FusedGenerator(const GeneratorNetImpl& net,
                          ProductPrecision precision = ProductPrecision::kFp32,
                          const std::vector<bool>& bf16_layers = {});
  ~FusedGenerator();
  FusedGenerator(FusedGenerator&&) noexcept;
  FusedGenerator& operator=(FusedGenerator&&) noexcept;

  // histories [Bh, t_his, N, 3] (root-relative, no root); z[p]: part p's latents [Bh * k, nz]
  // (sample b = h * k + j); fixed: as GeneratorNet::Decode. Writes futures [Bh * k, t_pred, N, 3].
  // Single-threaded; concurrent calls on one object are safe.
  void Predict(const float* histories, int64_t num_histories, int64_t k,
               const std::vector<const float*>& z, const std::vector<bool>& fixed,
               float* futures) const;

 private:
  struct Model;
  std::unique_ptr<Model> model_;
};

}  // namespace motionfork
