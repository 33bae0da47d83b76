#include "generator/model/fused_ops.h"

#include <ATen/Parallel.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

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

// Sums over the workers of per-(node, feature) values: `parts` float tensors [N, 1, H] (or
// [N, H]), each scaled by its factor, then `extra` values appended; returns the sums in double.
std::vector<double> SumOverWorkers(const BatchSync& sync,
                                   const std::vector<std::pair<torch::Tensor, double>>& parts,
                                   const std::vector<double>& extra) {
  std::vector<double> values;
  size_t size = extra.size();
  for (const auto& part : parts) size += static_cast<size_t>(part.first.numel());
  values.reserve(size);
  for (const auto& [t, factor] : parts) {
    const float* p = t.data_ptr<float>();
    for (int64_t i = 0; i < t.numel(); ++i) values.push_back(factor * p[i]);
  }
  values.insert(values.end(), extra.begin(), extra.end());
  sync.sum(&values);
  return values;
}

class BatchNormTanhFn : public torch::autograd::Function<BatchNormTanhFn> {
 public:
  // Returns {y, mean, var, rows}; only y carries a gradient. Saves x (not the normalised x: the
  // backward pass recomputes it, one fewer [N, B, H] tensor written and kept).
  static variable_list forward(AutogradContext* ctx, const torch::Tensor& x_in,
                               const torch::Tensor& gamma_in, const torch::Tensor& beta_in,
                               const torch::Tensor& bias, double eps, const BatchSync* sync) {
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
    double rows = static_cast<double>(B);
    if (!sync) {
      at::parallel_for(0, N, 1, [&](int64_t n0, int64_t n1) {
        for (int64_t n = n0; n < n1; ++n) {
          const int64_t o = n * B * H, c = n * H;
          kernels::BatchNormTanhForward(px + o, B, H, pg + c, pb + c, static_cast<float>(eps),
                                        pm + c, pv + c, pi + c, py + o);
        }
      });
    } else {
      at::parallel_for(0, N, 1, [&](int64_t n0, int64_t n1) {
        for (int64_t n = n0; n < n1; ++n)
          kernels::BatchMoments(px + n * B * H, B, H, pm + n * H, pv + n * H);
      });
      // Each worker's sum and sum of squares (in double: the whole batch's variance is their
      // difference), and its rows.
      const torch::Tensor square = var + mean * mean;
      const std::vector<double> sums =
          SumOverWorkers(*sync, {{mean, rows}, {square, rows}}, {rows});
      rows = sums.back();
      const int64_t NH = N * H;
      for (int64_t i = 0; i < NH; ++i) {
        const double m = sums[i] / rows;
        pm[i] = static_cast<float>(m);
        pv[i] = static_cast<float>(std::max(0.0, sums[NH + i] / rows - m * m));
        pi[i] = static_cast<float>(1.0 / std::sqrt(static_cast<double>(pv[i]) + eps));
      }
      at::parallel_for(0, N, 1, [&](int64_t n0, int64_t n1) {
        for (int64_t n = n0; n < n1; ++n) {
          const int64_t o = n * B * H, c = n * H;
          kernels::NormaliseTanh(px + o, B, H, pm + c, pi + c, pg + c, pb + c, py + o);
        }
      });
      // (A pointer is no IValue: it is kept as an integer until backward.)
      ctx->saved_data["sync"] = static_cast<int64_t>(reinterpret_cast<intptr_t>(sync));
    }
    ctx->save_for_backward({x, y, gamma, mean, inv});
    const torch::Tensor shifted = mean + bias.view({1, 1, H});  // the statistics of x + bias
    const torch::Tensor count = torch::scalar_tensor(rows, torch::kDouble);
    ctx->mark_non_differentiable({shifted, var, count});
    return {y, shifted, var, count};
  }

  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor &x = saved[0], &y = saved[1], &gamma = saved[2], &mean = saved[3],
                        &inv = saved[4];
    const torch::Tensor gy = grad[0].contiguous();
    const int64_t N = y.size(0), B = y.size(1), H = y.size(2);
    torch::Tensor gx = torch::empty_like(y), ggamma = torch::empty({N, 1, H}),
                  gbeta = torch::empty({N, 1, H});
    const float *px = x.data_ptr<float>(), *py = y.data_ptr<float>(), *pgy = gy.data_ptr<float>(),
                *pm = mean.data_ptr<float>(), *pi = inv.data_ptr<float>(),
                *pg = gamma.data_ptr<float>();
    float *pgx = gx.data_ptr<float>(), *pgg = ggamma.data_ptr<float>(),
          *pgb = gbeta.data_ptr<float>();
    const auto found = ctx->saved_data.find("sync");
    if (found == ctx->saved_data.end()) {
      at::parallel_for(0, N, 1, [&](int64_t n0, int64_t n1) {
        for (int64_t n = n0; n < n1; ++n) {
          const int64_t o = n * B * H, c = n * H;
          kernels::BatchNormTanhBackward(pgy + o, px + o, py + o, pm + c, pi + c, pg + c, B, H,
                                         pgx + o, pgg + c, pgb + c);
        }
      });
    } else {
      const auto* sync =
          reinterpret_cast<const BatchSync*>(static_cast<intptr_t>(found->second.toInt()));
      at::parallel_for(0, N, 1, [&](int64_t n0, int64_t n1) {
        for (int64_t n = n0; n < n1; ++n) {
          const int64_t o = n * B * H, c = n * H;
          kernels::TanhNormGradSums(pgy + o, px + o, py + o, pm + c, pi + c, B, H, pgx + o, pgg + c,
                                    pgb + c);
        }
      });
      // The loss is the share-weighted sum of the workers' losses, so this worker's gradient
      // (scaled by 1 / share when the gradients are summed) sees the others' sums weighted by
      // their shares: dL/dx = gamma * inv * (gu - sum_w share_w gbeta_w / B - xhat * (same for
      // ggamma) / B) for this worker's B rows.
      const std::vector<double> sums =
          SumOverWorkers(*sync, {{gbeta, sync->share}, {ggamma, sync->share}}, {});
      const int64_t NH = N * H;
      torch::Tensor total = torch::empty({2, NH});
      float* pt = total.data_ptr<float>();
      for (int64_t i = 0; i < 2 * NH; ++i) pt[i] = static_cast<float>(sums[i]);
      at::parallel_for(0, N, 1, [&](int64_t n0, int64_t n1) {
        for (int64_t n = n0; n < n1; ++n) {
          const int64_t o = n * B * H, c = n * H;
          kernels::NormGradInput(pgx + o, px + o, pm + c, pi + c, pg + c, B, H,
                                 static_cast<float>(B), pt + c, pt + NH + c);
        }
      });
    }
    // The normalisation cancels the bias: its gradient is zero (summing x's gradient would give
    // rounding noise, which Adam, normalising by the gradient's scale, turns into steps).
    return {gx, ggamma, gbeta, torch::zeros({H}), torch::Tensor(), torch::Tensor()};
  }
};

}  // namespace

torch::Tensor FusedTanh(const torch::Tensor& x) { return FusedTanhFn::apply(x); }

torch::Tensor BatchNormTanh(const torch::Tensor& x, const torch::Tensor& gamma,
                            const torch::Tensor& beta, double eps, torch::Tensor* mean,
                            torch::Tensor* var, const torch::Tensor& bias, const BatchSync* sync,
                            double* rows) {
  // (An autograd function's inputs must all be defined: no bias is a zero one.)
  const torch::Tensor b = bias.defined() ? bias : torch::zeros({x.size(2)});
  variable_list out = BatchNormTanhFn::apply(x, gamma, beta, b, eps, sync);
  if (mean) *mean = out[1];
  if (var) *var = out[2];
  if (rows) *rows = out[3].item<double>();
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
