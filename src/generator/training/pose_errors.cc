#include "generator/training/pose_errors.h"

#include <ATen/Parallel.h>

#include <cmath>
#include <stdexcept>

namespace motionfork {

namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

struct Sizes {
  int64_t Bh, K, T, N, t_his;
};

Sizes SizesOf(const torch::Tensor& pred, int64_t t_his) {
  return {pred.size(0), pred.size(1), pred.size(2), pred.size(3), t_his};
}

// Sample i's predicted frames [T, N, 3] and its history's true frames.
struct Sample {
  const float* pred;
  const float* truth;
  int64_t history;  // b in [0, Bh)
};

inline Sample SampleAt(const Sizes& s, const float* pred, const float* truth, int64_t i) {
  const int64_t frames = s.T * s.N * 3, b = i / s.K;
  return {pred + i * frames, truth + b * frames, b};
}

// Bone length of node n in one pose p [N, 3]; its vector to *d.
inline float Bone(const float* p, int64_t n, int64_t parent, float d[3]) {
  for (int c = 0; c < 3; ++c) d[c] = p[n * 3 + c] - (parent < 0 ? 0.0f : p[parent * 3 + c]);
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

class PoseErrorsFn : public torch::autograd::Function<PoseErrorsFn> {
 public:
  // truth_len [Bh, N]: the truth's bone lengths at frame t_his - 1.
  static variable_list forward(AutogradContext* ctx, const torch::Tensor& pred_in,
                               const torch::Tensor& truth_in, const torch::Tensor& truth_len_in,
                               int64_t t_his, std::vector<int64_t> parents) {
    const torch::Tensor pred = pred_in.contiguous(), truth = truth_in.contiguous(),
                        truth_len = truth_len_in.contiguous();
    const Sizes s = SizesOf(pred, t_his);
    torch::Tensor past = torch::empty({s.Bh, s.K}), future = torch::empty({s.Bh, s.K}),
                  future_norm = torch::empty({s.Bh, s.K}), limb = torch::empty({s.Bh, s.K, s.T});
    const float *pp = pred.data_ptr<float>(), *pt = truth.data_ptr<float>(),
                *pl = truth_len.data_ptr<float>();
    float *o_past = past.data_ptr<float>(), *o_future = future.data_ptr<float>(),
          *o_norm = future_norm.data_ptr<float>(), *o_limb = limb.data_ptr<float>();
    const int64_t pose = s.N * 3;
    at::parallel_for(0, s.Bh * s.K, 1, [&](int64_t i0, int64_t i1) {
      for (int64_t i = i0; i < i1; ++i) {
        const auto [p, t, b] = SampleAt(s, pp, pt, i);
        double e_past = 0, e_future = 0, norm = 0;
        for (int64_t f = 0; f < s.T; ++f) {
          double e = 0, q = 0;
          for (int64_t j = 0; j < pose; ++j) {
            const float v = p[f * pose + j], d = v - t[f * pose + j];
            e += d * d;
            q += v * v;
          }
          if (f < s.t_his) {
            e_past += e;
          } else {
            e_future += e;
            norm += q;
          }
          double l = 0;
          for (int64_t n = 0; n < s.N; ++n) {
            float d[3];
            const float err = Bone(p + f * pose, n, parents[n], d) - pl[b * s.N + n];
            l += err * err;
          }
          o_limb[i * s.T + f] = static_cast<float>(l);
        }
        o_past[i] = static_cast<float>(e_past / static_cast<double>(s.t_his));
        o_future[i] = static_cast<float>(e_future);
        o_norm[i] = static_cast<float>(norm);
      }
    });
    ctx->save_for_backward({pred, truth, truth_len});
    ctx->saved_data["t_his"] = t_his;
    ctx->saved_data["parents"] = c10::List<int64_t>(parents);
    return {past, future, future_norm, limb};
  }

  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor &pred = saved[0], &truth = saved[1], &truth_len = saved[2];
    const int64_t t_his = ctx->saved_data["t_his"].toInt();
    const std::vector<int64_t> parents = ctx->saved_data["parents"].toIntVector();
    const Sizes s = SizesOf(pred, t_his);
    // An output that no loss used has no gradient: it counts as zero.
    auto contiguous_or_zeros = [](const torch::Tensor& g, at::IntArrayRef sizes) {
      return g.defined() ? g.contiguous() : torch::zeros(sizes);
    };
    const torch::Tensor g_past = contiguous_or_zeros(grad[0], {s.Bh, s.K});
    const torch::Tensor g_future = contiguous_or_zeros(grad[1], {s.Bh, s.K});
    const torch::Tensor g_norm = contiguous_or_zeros(grad[2], {s.Bh, s.K});
    const torch::Tensor g_limb = contiguous_or_zeros(grad[3], {s.Bh, s.K, s.T});
    torch::Tensor g_pred = torch::empty_like(pred);
    const float *pp = pred.data_ptr<float>(), *pt = truth.data_ptr<float>(),
                *pl = truth_len.data_ptr<float>();
    const float *gp = g_past.data_ptr<float>(), *gf = g_future.data_ptr<float>(),
                *gn = g_norm.data_ptr<float>(), *gl = g_limb.data_ptr<float>();
    float* out = g_pred.data_ptr<float>();
    const int64_t pose = s.N * 3;
    at::parallel_for(0, s.Bh * s.K, 1, [&](int64_t i0, int64_t i1) {
      for (int64_t i = i0; i < i1; ++i) {
        const auto [p, t, b] = SampleAt(s, pp, pt, i);
        float* g = out + i * s.T * pose;
        const float past = 2.0f * gp[i] / static_cast<float>(s.t_his), future = 2.0f * gf[i],
                    norm = 2.0f * gn[i];
        for (int64_t f = 0; f < s.T; ++f) {
          const float* pf = p + f * pose;
          const float* tf = t + f * pose;
          float* gf_ = g + f * pose;
          if (f < s.t_his) {
            for (int64_t j = 0; j < pose; ++j) gf_[j] = past * (pf[j] - tf[j]);
          } else {
            for (int64_t j = 0; j < pose; ++j) gf_[j] = future * (pf[j] - tf[j]) + norm * pf[j];
          }
          const float w = 2.0f * gl[i * s.T + f];
          if (w == 0.0f) continue;
          for (int64_t n = 0; n < s.N; ++n) {
            float d[3];
            const float len = Bone(pf, n, parents[n], d);
            if (len == 0.0f) continue;  // as LibTorch's norm: no gradient at zero length
            const float k = w * (len - pl[b * s.N + n]) / len;
            for (int c = 0; c < 3; ++c) {
              gf_[n * 3 + c] += k * d[c];
              if (parents[n] >= 0) gf_[parents[n] * 3 + c] -= k * d[c];
            }
          }
        }
      }
    });
    return {g_pred, torch::Tensor(), torch::Tensor(), torch::Tensor(), torch::Tensor()};
  }
};

}  // namespace

PoseErrors ComputePoseErrors(const torch::Tensor& pred, const torch::Tensor& truth, int64_t t_his,
                             const std::vector<int64_t>& node_parents) {
  if (pred.dim() != 5 || truth.dim() != 4 || pred.size(0) != truth.size(0) ||
      pred.size(2) != truth.size(1) || pred.size(3) != truth.size(2) || pred.size(4) != 3 ||
      truth.size(3) != 3 || static_cast<int64_t>(node_parents.size()) != pred.size(3) ||
      t_his < 1 || t_his >= pred.size(2)) {
    throw std::invalid_argument(
        "pose errors: expected pred [Bh, K, T, N, 3] and truth [Bh, T, N, 3] with N = " +
        std::to_string(node_parents.size()) + " and 0 < t_his < T, got " + c10::str(pred.sizes()) +
        " and " + c10::str(truth.sizes()));
  }
  // The truth's bone lengths at the last history frame [Bh, N] (constant), as the predictions' are
  // measured.
  const int64_t Bh = truth.size(0), N = truth.size(2);
  const torch::Tensor last = truth.detach().select(1, t_his - 1).contiguous();
  torch::Tensor truth_len = torch::empty({Bh, N});
  const float* pose = last.data_ptr<float>();
  float* len = truth_len.data_ptr<float>();
  for (int64_t b = 0; b < Bh; ++b) {
    for (int64_t n = 0; n < N; ++n) {
      float d[3];
      len[b * N + n] = Bone(pose + b * N * 3, n, node_parents[n], d);
    }
  }
  const variable_list out =
      PoseErrorsFn::apply(pred, truth.detach(), truth_len, t_his, node_parents);
  return {out[0], out[1], out[2], out[3]};
}

}  // namespace motionfork
