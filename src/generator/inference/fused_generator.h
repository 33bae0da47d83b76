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

// The inputs of the hidden layers' products (H x H, nearly all of the work): float32, or bfloat16
// with float32 sums (kernels/bf16_product.h: the AVX512-BF16 kernel where the CPU has it, a slow
// portable one elsewhere). The input and output layers, the latent's product and the inverse DCT
// stay float32 (small; the output layer in bf16 had doubled the futures' deviation), as do batch
// norm, tanh and the DCT.
enum class ProductPrecision { kFp32, kBf16 };

class FusedGenerator {
 public:
  // Copies the network's eval-mode weights; the network may change or go afterwards.
  explicit FusedGenerator(const GeneratorNetImpl& net,
                          ProductPrecision precision = ProductPrecision::kFp32);
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
