#include "generator/fused_ops.h"

#include <Eigen/Core>

#include "generator/fast_tanh.h"

namespace motionfork {

namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;
using Row = Eigen::Map<Eigen::ArrayXf>;
using ConstRow = Eigen::Map<const Eigen::ArrayXf>;

class FastTanhFn : public torch::autograd::Function<FastTanhFn> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& x) {
    torch::Tensor y = x.contiguous().clone();
    fast::Tanh(y.data_ptr<float>(), y.numel());
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
  // Returns {y, mean, var}; only y carries a gradient.
  static variable_list forward(AutogradContext* ctx, const torch::Tensor& x_in,
                               const torch::Tensor& gamma_in, const torch::Tensor& beta_in, double eps) {
    const torch::Tensor x = x_in.contiguous();
    const torch::Tensor gamma = gamma_in.contiguous(), beta = beta_in.contiguous();
    const int64_t N = x.size(0), B = x.size(1), H = x.size(2);
    torch::Tensor xhat = torch::empty_like(x), y = torch::empty_like(x);
    torch::Tensor mean = torch::empty({N, 1, H}), var = torch::empty({N, 1, H}), inv = torch::empty({N, 1, H});
    const float* px = x.data_ptr<float>();
    float* pxhat = xhat.data_ptr<float>();
    float* py = y.data_ptr<float>();
    for (int64_t n = 0; n < N; ++n) {
      Row m(mean.data_ptr<float>() + n * H, H), v(var.data_ptr<float>() + n * H, H),
          iv(inv.data_ptr<float>() + n * H, H);
      m.setZero();
      v.setZero();
      for (int64_t b = 0; b < B; ++b) m += ConstRow(px + (n * B + b) * H, H);
      m /= static_cast<float>(B);
      for (int64_t b = 0; b < B; ++b) v += (ConstRow(px + (n * B + b) * H, H) - m).square();
      v /= static_cast<float>(B);
      iv = (v + static_cast<float>(eps)).rsqrt();
      ConstRow g(gamma.data_ptr<float>() + n * H, H), be(beta.data_ptr<float>() + n * H, H);
      for (int64_t b = 0; b < B; ++b) {
        const int64_t o = (n * B + b) * H;
        Row xh(pxhat + o, H);
        xh = (ConstRow(px + o, H) - m) * iv;
        Row(py + o, H) = xh * g + be;
      }
    }
    fast::Tanh(py, y.numel());
    ctx->save_for_backward({xhat, y, gamma, inv});
    ctx->mark_non_differentiable({mean, var});
    return {y, mean, var};
  }

  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor &xhat = saved[0], &y = saved[1], &gamma = saved[2], &inv = saved[3];
    const torch::Tensor gy = grad[0].contiguous();
    const int64_t N = y.size(0), B = y.size(1), H = y.size(2);
    torch::Tensor gx = torch::empty_like(y), ggamma = torch::empty({N, 1, H}),
                  gbeta = torch::empty({N, 1, H});
    const float *pxh = xhat.data_ptr<float>(), *py = y.data_ptr<float>(), *pgy = gy.data_ptr<float>();
    float* pgx = gx.data_ptr<float>();
    for (int64_t n = 0; n < N; ++n) {
      Row gg(ggamma.data_ptr<float>() + n * H, H), gb(gbeta.data_ptr<float>() + n * H, H);
      gg.setZero();
      gb.setZero();
      // gu = gy * (1 - y^2), kept in gx for now.
      for (int64_t b = 0; b < B; ++b) {
        const int64_t o = (n * B + b) * H;
        Row gu(pgx + o, H);
        const ConstRow yy(py + o, H);
        gu = ConstRow(pgy + o, H) * (1.0f - yy * yy);
        gb += gu;
        gg += gu * ConstRow(pxh + o, H);
      }
      // gx = gamma * inv / B * (B * gu - sum(gu) - xhat * sum(gu * xhat))
      const Eigen::ArrayXf k = ConstRow(gamma.data_ptr<float>() + n * H, H) *
                               ConstRow(inv.data_ptr<float>() + n * H, H) / static_cast<float>(B);
      for (int64_t b = 0; b < B; ++b) {
        const int64_t o = (n * B + b) * H;
        Row g(pgx + o, H);
        g = k * (static_cast<float>(B) * g - gb - ConstRow(pxh + o, H) * gg);
      }
    }
    return {gx, ggamma, gbeta, torch::Tensor()};
  }
};

}  // namespace

torch::Tensor FastTanh(const torch::Tensor& x) { return FastTanhFn::apply(x); }

torch::Tensor BatchNormTanh(const torch::Tensor& x, const torch::Tensor& gamma,
                            const torch::Tensor& beta, double eps, torch::Tensor* mean,
                            torch::Tensor* var) {
  variable_list out = BatchNormTanhFn::apply(x, gamma, beta, eps);
  if (mean) *mean = out[1];
  if (var) *var = out[2];
  return out[0];
}

torch::Tensor ScaleShiftTanh(const torch::Tensor& x, const torch::Tensor& scale,
                             const torch::Tensor& shift) {
  torch::Tensor y = x.contiguous().clone();
  const torch::Tensor s = scale.contiguous(), t = shift.contiguous();
  fast::ScaleShiftTanh(y.data_ptr<float>(), s.data_ptr<float>(), t.data_ptr<float>(),
                       y.size(0) * y.size(1), y.size(1), y.size(2));
  return y;
}

}  // namespace motionfork
