#include "generator/model/fused_ops.h"

#include <ATen/Parallel.h>

#include <algorithm>

#include "generator/kernels/batch_norm_tanh.h"
#include "generator/kernels/tanh.h"

namespace motionfork {

namespace {

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

}  // namespace

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
