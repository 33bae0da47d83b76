#include "generator/model/fused_ops.h"

#include <ATen/Parallel.h>

#include <algorithm>

#include "generator/kernels/backend.h"
#include "generator/kernels/batch_norm_tanh.h"
#include "generator/kernels/node_mix.h"
#include "generator/kernels/panel_product.h"
#include "generator/kernels/tanh.h"

namespace motionfork {

namespace {

// The AVX-512 kernels without a portable twin here (node mix, weight product) run only then;
// otherwise LibTorch's matrix product does their work.
bool UseAvx512() { return kernels::ActiveBackend() == kernels::Backend::kAvx512; }

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

class FusedTanhFn : public torch::autograd::Function<FusedTanhFn> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& x) {
    torch::Tensor y = x.contiguous().clone();
    kernels::Tanh(y.data_ptr<float>(), y.numel());
    ctx->save_for_backward({y});
    return y;
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    const torch::Tensor y = ctx->get_saved_variables()[0];
    return {grad[0] * (1 - y * y)};
  }
};

class BatchNormTanhFn : public torch::autograd::Function<BatchNormTanhFn> {
 public:
  // Returns {y, mean, var}; only y carries a gradient. Saves x (not the normalised x: the
  // backward pass recomputes it, one fewer [N, B, H] tensor written and kept).
  static variable_list forward(AutogradContext* ctx, const torch::Tensor& x_in,
                               const torch::Tensor& gamma_in, const torch::Tensor& beta_in,
                               const torch::Tensor& bias, double eps) {
    const torch::Tensor x = x_in.contiguous();
    const torch::Tensor gamma = gamma_in.contiguous(), beta = beta_in.contiguous();
    const int64_t N = x.size(0), B = x.size(1), H = x.size(2);
    torch::Tensor y = torch::empty_like(x);
    torch::Tensor mean = torch::empty({N, 1, H}), var = torch::empty({N, 1, H}),
                  inv = torch::empty({N, 1, H});
    const float *px = x.data_ptr<float>(), *pg = gamma.data_ptr<float>(),
                *pb = beta.data_ptr<float>();
    float *py = y.data_ptr<float>(), *pm = mean.data_ptr<float>(), *pv = var.data_ptr<float>(),
          *pi = inv.data_ptr<float>();
    at::parallel_for(0, N, 1, [&](int64_t n0, int64_t n1) {
      for (int64_t n = n0; n < n1; ++n) {
        const int64_t o = n * B * H, c = n * H;
        kernels::BatchNormTanhForward(px + o, B, H, pg + c, pb + c, static_cast<float>(eps), pm + c,
                                      pv + c, pi + c, py + o);
      }
    });
    ctx->save_for_backward({x, y, gamma, mean, inv});
    const torch::Tensor shifted = mean + bias.view({1, 1, H});  // the statistics of x + bias
    ctx->mark_non_differentiable({shifted, var});
    return {y, shifted, var};
  }

  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor &x = saved[0], &y = saved[1], &gamma = saved[2], &mean = saved[3],
                        &inv = saved[4];
    const torch::Tensor gy = grad[0].contiguous();
    const int64_t N = y.size(0), B = y.size(1), H = y.size(2);
    torch::Tensor gx = torch::empty_like(y), ggamma = torch::empty({N, 1, H}),
                  gbeta = torch::empty({N, 1, H}), gsum = torch::empty({N, H});
    const float *px = x.data_ptr<float>(), *py = y.data_ptr<float>(), *pgy = gy.data_ptr<float>(),
                *pm = mean.data_ptr<float>(), *pi = inv.data_ptr<float>(),
                *pg = gamma.data_ptr<float>();
    float *pgx = gx.data_ptr<float>(), *pgg = ggamma.data_ptr<float>(),
          *pgb = gbeta.data_ptr<float>(), *pgs = gsum.data_ptr<float>();
    at::parallel_for(0, N, 1, [&](int64_t n0, int64_t n1) {
      for (int64_t n = n0; n < n1; ++n) {
        const int64_t o = n * B * H, c = n * H;
        kernels::BatchNormTanhBackward(pgy + o, px + o, py + o, pm + c, pi + c, pg + c, B, H,
                                       pgx + o, pgg + c, pgb + c, pgs + c);
      }
    });
    return {gx, ggamma, gbeta, gsum.sum(0), torch::Tensor()};
  }
};

// y = A x on node-major [N, C] views, columns split over the threads.
torch::Tensor MixNodes(const torch::Tensor& a, const torch::Tensor& x) {
  const int64_t N = x.size(0), C = x.numel() / N;
  torch::Tensor y = torch::empty_like(x);
  const float *pa = a.data_ptr<float>(), *px = x.data_ptr<float>();
  float* py = y.data_ptr<float>();
  at::parallel_for(0, C, 4096,
                   [&](int64_t j0, int64_t j1) { kernels::NodeMix(pa, N, px, C, j0, j1, py); });
  return y;
}

class NodeMixFn : public torch::autograd::Function<NodeMixFn> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& a_in,
                               const torch::Tensor& x_in) {
    const torch::Tensor a = a_in.contiguous(), x = x_in.contiguous();
    ctx->save_for_backward({a, x});
    return MixNodes(a, x);
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor &a = saved[0], &x = saved[1], g = grad[0].contiguous();
    const int64_t N = x.size(0);
    const torch::Tensor a_t = a.t().contiguous();
    if (!ctx->needs_input_grad(0)) return {torch::Tensor(), MixNodes(a_t, g)};
    // Both in one pass over g and x; dA's sums per thread's column range, added up after.
    const int64_t C = x.numel() / N, ranges = std::max<int64_t>(1, at::get_num_threads());
    const int64_t width = ((C + ranges - 1) / ranges + 63) / 64 * 64;
    torch::Tensor gx = torch::empty_like(x), partial = torch::zeros({ranges, N, N});
    const float *pa = a_t.data_ptr<float>(), *pg = g.data_ptr<float>(), *px = x.data_ptr<float>();
    float *pgx = gx.data_ptr<float>(), *pp = partial.data_ptr<float>();
    at::parallel_for(0, ranges, 1, [&](int64_t r0, int64_t r1) {
      for (int64_t r = r0; r < r1; ++r) {
        const int64_t j0 = std::min(C, r * width), j1 = std::min(C, j0 + width);
        if (j0 < j1) kernels::NodeMixBackward(pa, N, pg, px, C, j0, j1, pgx, pp + r * N * N);
      }
    });
    return {partial.sum(0), ctx->needs_input_grad(1) ? gx : torch::Tensor()};
  }
};

// Fewer rows do not pay for packing W (inference's small products stay with LibTorch's mm).
constexpr int64_t kMinKernelRows = 4096;

// x [M, K] w [K, H] with kernels::MatMul, rows split over the threads; LibTorch's mm unless H is a
// multiple of 16 (the kernel writes rows padded to one). The caller has checked the CPU, the type
// and the rows (the same for x W and g W^T).
torch::Tensor PanelProduct(const torch::Tensor& x_in, const torch::Tensor& w_in) {
  if (w_in.size(1) % 16 != 0) return x_in.mm(w_in);
  const torch::Tensor x = x_in.contiguous(), w = w_in.contiguous();
  const int64_t M = x.size(0), K = x.size(1), H = w.size(1);
  const kernels::PackedWeight packed = kernels::PackWeight(w.data_ptr<float>(), K, H);
  torch::Tensor z = torch::empty({M, H});
  const float* px = x.data_ptr<float>();
  float* pz = z.data_ptr<float>();
  at::parallel_for(0, M, 768, [&](int64_t r0, int64_t r1) {
    kernels::MatMul(px + r0 * K, r1 - r0, K, packed, pz + r0 * H);
  });
  return z;
}

class WeightProductFn : public torch::autograd::Function<WeightProductFn> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& x,
                               const torch::Tensor& w) {
    ctx->save_for_backward({x, w});
    return PanelProduct(x, w);
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor &x = saved[0], &w = saved[1], g = grad[0].contiguous();
    return {ctx->needs_input_grad(0) ? PanelProduct(g, w.t()) : torch::Tensor(),
            ctx->needs_input_grad(1) ? x.t().mm(g) : torch::Tensor()};
  }
};

}  // namespace

torch::Tensor WeightProduct(const torch::Tensor& x, const torch::Tensor& w) {
  if (!UseAvx512() || x.size(0) < kMinKernelRows || x.scalar_type() != torch::kFloat)
    return x.mm(w);
  return WeightProductFn::apply(x, w);
}

torch::Tensor NodeMix(const torch::Tensor& adjacency, const torch::Tensor& x) {
  if (!UseAvx512() || x.scalar_type() != torch::kFloat) {
    return adjacency.mm(x.reshape({x.size(0), -1})).view(x.sizes());
  }
  return NodeMixFn::apply(adjacency, x);
}

torch::Tensor FusedTanh(const torch::Tensor& x) { return FusedTanhFn::apply(x); }

torch::Tensor BatchNormTanh(const torch::Tensor& x, const torch::Tensor& gamma,
                            const torch::Tensor& beta, double eps, torch::Tensor* mean,
                            torch::Tensor* var, const torch::Tensor& bias) {
  // (An autograd function's inputs must all be defined: no bias is a zero one.)
  const torch::Tensor b = bias.defined() ? bias : torch::zeros({x.size(2)});
  variable_list out = BatchNormTanhFn::apply(x, gamma, beta, b, eps);
  if (mean) *mean = out[1];
  if (var) *var = out[2];
  return out[0];
}

torch::Tensor ScaleShiftTanh(const torch::Tensor& x, const torch::Tensor& scale,
                             const torch::Tensor& shift) {
  torch::Tensor y = x.contiguous().clone();
  const torch::Tensor s = scale.contiguous(), t = shift.contiguous();
  kernels::ScaleShiftTanh(y.data_ptr<float>(), s.data_ptr<float>(), t.data_ptr<float>(),
                          y.size(0) * y.size(1), y.size(1), y.size(2));
  return y;
}

}  // namespace motionfork
