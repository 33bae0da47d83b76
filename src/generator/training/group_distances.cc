#include "generator/training/group_distances.h"

#include <ATen/Parallel.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace motionfork {

namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

// Where the compared values live in pred: frames t_from..T-1, the listed nodes, three axes. A
// group's copy of them is contiguous, [n, width()].
struct Layout {
  int64_t T, N, t_from;
  std::vector<int64_t> nodes;
  int64_t width() const { return (T - t_from) * static_cast<int64_t>(nodes.size()) * 3; }
};

// rows: one group's n sample indices.
void Gather(const Layout& l, const float* pred, const int64_t* rows, int64_t n, float* out) {
  for (int64_t row : c10::ArrayRef<int64_t>(rows, n)) {
    for (int64_t t = l.t_from; t < l.T; ++t) {
      const float* frame = pred + (row * l.T + t) * l.N * 3;
      for (int64_t node : l.nodes)
        for (int c = 0; c < 3; ++c) *out++ = frame[node * 3 + c];
    }
  }
}

void Scatter(const Layout& l, const float* in, const int64_t* rows, int64_t n, float* grad) {
  for (int64_t row : c10::ArrayRef<int64_t>(rows, n)) {
    for (int64_t t = l.t_from; t < l.T; ++t) {
      float* frame = grad + (row * l.T + t) * l.N * 3;
      for (int64_t node : l.nodes)
        for (int c = 0; c < 3; ++c) frame[node * 3 + c] = *in++;
    }
  }
}

// Sum of |a - b| over D values, in 16 partial sums (vectorisable, and less rounding than one).
float L1(const float* a, const float* b, int64_t D) {
  float part[16] = {};
  int64_t d = 0;
  for (; d + 16 <= D; d += 16)
    for (int k = 0; k < 16; ++k) part[k] += std::fabs(a[d + k] - b[d + k]);
  double sum = 0;
  for (; d < D; ++d) sum += std::fabs(a[d] - b[d]);
  for (float p : part) sum += p;
  return static_cast<float>(sum);
}

inline float Sign(float v) { return static_cast<float>((v > 0) - (v < 0)); }

class GroupL1Fn : public torch::autograd::Function<GroupL1Fn> {
 public:
  // rows: [G, n] int64.
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& pred_in,
                               const torch::Tensor& rows, Layout layout) {
    const torch::Tensor pred = pred_in.contiguous();
    const int64_t G = rows.size(0), n = rows.size(1), D = layout.width();
    const int64_t* r = rows.data_ptr<int64_t>();
    torch::Tensor dist = torch::zeros({G, n, n});
    float* out = dist.data_ptr<float>();
    const float* p = pred.data_ptr<float>();
    at::parallel_for(0, G, 1, [&](int64_t g0, int64_t g1) {
      std::vector<float> x(static_cast<size_t>(n * D));
      for (int64_t g = g0; g < g1; ++g) {
        Gather(layout, p, r + g * n, n, x.data());
        for (int64_t i = 0; i < n; ++i)
          for (int64_t j = i + 1; j < n; ++j) {
            out[(g * n + i) * n + j] = out[(g * n + j) * n + i] = L1(&x[i * D], &x[j * D], D);
          }
      }
    });
    ctx->save_for_backward({pred});
    ctx->saved_data["rows"] = rows;
    ctx->saved_data["T"] = layout.T;
    ctx->saved_data["N"] = layout.N;
    ctx->saved_data["t_from"] = layout.t_from;
    ctx->saved_data["nodes"] = c10::IValue(layout.nodes);
    return dist;
  }

  static variable_list backward(AutogradContext* ctx, variable_list grad_out) {
    const torch::Tensor pred = ctx->get_saved_variables()[0];
    const torch::Tensor rows = ctx->saved_data["rows"].toTensor();
    const Layout layout{ctx->saved_data["T"].toInt(), ctx->saved_data["N"].toInt(),
                        ctx->saved_data["t_from"].toInt(), ctx->saved_data["nodes"].toIntVector()};
    const torch::Tensor g = grad_out[0].contiguous();
    const int64_t G = rows.size(0), n = rows.size(1), D = layout.width();
    const int64_t* r = rows.data_ptr<int64_t>();
    // Only the groups' values get a gradient; the rest of pred's stays zero.
    torch::Tensor grad = torch::zeros_like(pred);
    const float *p = pred.data_ptr<float>(), *gp = g.data_ptr<float>();
    float* out = grad.data_ptr<float>();
    at::parallel_for(0, G, 1, [&](int64_t g0, int64_t g1) {
      std::vector<float> x(static_cast<size_t>(n * D)), gx(static_cast<size_t>(n * D));
      for (int64_t gi = g0; gi < g1; ++gi) {
        Gather(layout, p, r + gi * n, n, x.data());
        std::fill(gx.begin(), gx.end(), 0.0f);
        for (int64_t i = 0; i < n; ++i)
          for (int64_t j = i + 1; j < n; ++j) {
            // d(i, j) appears twice in the output; both entries' gradients reach the pair.
            const float w = gp[(gi * n + i) * n + j] + gp[(gi * n + j) * n + i];
            if (w == 0.0f) continue;
            const float *a = &x[i * D], *b = &x[j * D];
            float *ga = &gx[i * D], *gb = &gx[j * D];
            for (int64_t d = 0; d < D; ++d) {
              const float s = w * Sign(a[d] - b[d]);
              ga[d] += s;
              gb[d] -= s;
            }
          }
        Scatter(layout, gx.data(), r + gi * n, n, out);
      }
    });
    return {grad, torch::Tensor(), torch::Tensor()};
  }
};

}  // namespace

torch::Tensor GroupL1Distances(const torch::Tensor& pred, const torch::Tensor& rows_in,
                               const std::vector<int64_t>& nodes, int64_t t_from) {
  if (pred.dim() != 4 || pred.size(3) != 3 || pred.scalar_type() != torch::kFloat) {
    throw std::invalid_argument("group distances: expected float predictions [B, T, N, 3], got " +
                                c10::str(pred.sizes()));
  }
  const int64_t B = pred.size(0), T = pred.size(1), N = pred.size(2);
  if (rows_in.dim() != 2 || rows_in.numel() == 0 || rows_in.scalar_type() != torch::kLong ||
      t_from < 0 || t_from >= T || nodes.empty()) {
    throw std::invalid_argument(
        "group distances: expected int64 sample indices [G, n] (not empty), >= 1 node "
        "and a first frame in 0.." +
        std::to_string(T - 1) + ", got " + c10::str(rows_in.sizes()) + " and t_from " +
        std::to_string(t_from));
  }
  const torch::Tensor rows = rows_in.contiguous();
  std::vector<char> seen(static_cast<size_t>(B), 0);
  const int64_t* r = rows.data_ptr<int64_t>();
  for (int64_t i = 0; i < rows.numel(); ++i) {
    if (r[i] < 0 || r[i] >= B || seen[r[i]]) {
      throw std::invalid_argument("group distances: sample " + std::to_string(r[i]) +
                                  " out of 0.." + std::to_string(B - 1) + " or in two groups");
    }
    seen[r[i]] = 1;
  }
  for (int64_t node : nodes) {
    if (node < 0 || node >= N) {
      throw std::invalid_argument("group distances: node " + std::to_string(node) + " out of 0.." +
                                  std::to_string(N - 1));
    }
  }
  return GroupL1Fn::apply(pred, rows, Layout{T, N, t_from, nodes});
}

}  // namespace motionfork
