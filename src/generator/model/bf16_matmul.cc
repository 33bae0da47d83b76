#include "generator/model/bf16_matmul.h"

#include <ATen/Parallel.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "generator/kernels/bf16_product.h"

namespace motionfork {

namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

// Rows of the product shared out among LibTorch's threads in blocks of this many (a multiple of
// the kernel's tile of 8 rows, so that only the last block runs a shorter tile).
constexpr int64_t kRowBlock = 64;

// a [M, K] (contiguous float32) times b [K, N] (contiguous float32), bf16 inputs, float32 sums.
torch::Tensor Product(const torch::Tensor& a, const torch::Tensor& b) {
  const int64_t M = a.size(0), K = a.size(1), N = b.size(1);
  const kernels::PackedWeightBf16 packed = kernels::PackWeightBf16(b.data_ptr<float>(), K, N);
  torch::Tensor out = torch::empty({M, N});
  const float* pa = a.data_ptr<float>();
  float* po = out.data_ptr<float>();
  // The kernel writes rows of `padded` floats at 64-byte aligned addresses: straight into the
  // result when its rows are already that, else through an aligned block copied out.
  const bool direct = packed.padded == N && reinterpret_cast<std::uintptr_t>(po) % 64 == 0;
  at::parallel_for(0, (M + kRowBlock - 1) / kRowBlock, 1, [&](int64_t b0, int64_t b1) {
    kernels::AlignedFloats block(direct ? 0 : kRowBlock * packed.padded, /*zero=*/false);
    for (int64_t blk = b0; blk < b1; ++blk) {
      const int64_t r0 = blk * kRowBlock, rows = std::min(kRowBlock, M - r0);
      if (direct) {
        kernels::MatMulBf16(pa + r0 * K, rows, K, packed, po + r0 * N);
        continue;
      }
      kernels::MatMulBf16(pa + r0 * K, rows, K, packed, block.get());
      for (int64_t r = 0; r < rows; ++r)
        std::memcpy(po + (r0 + r) * N, block.get() + r * packed.padded, N * sizeof(float));
    }
  });
  return out;
}

class Bf16MatMulFn : public torch::autograd::Function<Bf16MatMulFn> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& x_in,
                               const torch::Tensor& w_in) {
    const torch::Tensor x = x_in.contiguous(), w = w_in.contiguous();
    ctx->save_for_backward({x, w});
    return Product(x, w);
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor &x = saved[0], &w = saved[1];
    const torch::Tensor dy = grad[0].contiguous();
    torch::Tensor dx, dw;
    if (ctx->needs_input_grad(0)) dx = Product(dy, w.t().contiguous());
    if (ctx->needs_input_grad(1)) dw = Product(x.t().contiguous(), dy);
    return {dx, dw};
  }
};

}  // namespace

torch::Tensor Bf16MatMul(const torch::Tensor& x, const torch::Tensor& w) {
  TORCH_CHECK(x.dim() == 2 && w.dim() == 2 && x.size(1) == w.size(0),
              "Bf16MatMul: expected x [M, K] and w [K, N], got ", x.sizes(), " and ", w.sizes());
  TORCH_CHECK(x.scalar_type() == torch::kFloat && w.scalar_type() == torch::kFloat,
              "Bf16MatMul: expected float32 tensors");
  return Bf16MatMulFn::apply(x, w);
}

}  // namespace motionfork
