#include "generator/training/losses.h"

#include <cmath>
#include <stdexcept>

#include "generator/training/group_distances.h"
#include "generator/training/pose_errors.h"

namespace motionfork {

namespace {

// poses [Bh, ...(, 3)] turned per history by b.world_turn about up (the ground axes a towards b).
torch::Tensor TurnedBack(const torch::Tensor& poses, const LossBatch& b) {
  const int64_t Bh = poses.size(0);
  if (static_cast<int64_t>(b.world_turn.size()) != Bh) {
    throw std::invalid_argument("losses: expected " + std::to_string(Bh) + " turns, got " +
                                std::to_string(b.world_turn.size()));
  }
  torch::Tensor r = torch::eye(3).repeat({Bh, 1, 1});  // [Bh, 3, 3], p' = r p
  float* m = r.data_ptr<float>();
  for (int64_t h = 0; h < Bh; ++h, m += 9) {
    const float c = static_cast<float>(std::cos(b.world_turn[h]));
    const float s = static_cast<float>(std::sin(b.world_turn[h]));
    m[3 * b.ground_a + b.ground_a] = c;
    m[3 * b.ground_a + b.ground_b] = -s;
    m[3 * b.ground_b + b.ground_a] = s;
    m[3 * b.ground_b + b.ground_b] = c;
  }
  return torch::matmul(poses.reshape({Bh, -1, 3}), r.transpose(1, 2)).view(poses.sizes());
}

}  // namespace

LossTerms ComputeLosses(const LossBatch& b, const LossWeights& w, const LossHooks& hooks,
                        int64_t prior_offset, int64_t prior_step) {
  const int64_t Bh = b.truth.size(0), T = b.truth.size(1), N = b.truth.size(2);
  int64_t K = 1;
  for (int64_t n : b.per_part) K *= n;
  if (b.pred.size(0) != Bh * K) {
    throw std::invalid_argument("losses: expected " + std::to_string(Bh * K) +
                                " predictions, got " + std::to_string(b.pred.size(0)));
  }
  const torch::Tensor pred = b.pred.view({Bh, K, T, N, 3});
  LossTerms out;
  auto add = [&](const std::string& name, const torch::Tensor& value, double weight) {
    out.terms.emplace_back(name, value);
    out.total = out.total.defined() ? out.total + weight * value : weight * value;
  };
  // Reductions as in GSPS's released training code, which its loss weights are tuned for: squared
  // distances summed over the whole pose (nodes x 3), averaged over past frames (history
  // reconstruction) or summed over future frames (best-of-many, pseudo multimodal futures).
  const PoseErrors errors = ComputePoseErrors(pred, b.truth, b.t_his, b.node_parents);
  add("past_reconstruction", errors.past.mean(), w.past_reconstruction);
  // Squared bone-length errors summed over the bones of a pose, averaged over poses (GSPS).
  add("limb_length", errors.limb.mean(), w.limb_length);

  // Diversity of each part among the samples that differ only in its own latent.
  int64_t before = 1;
  for (size_t p = 0; p < b.per_part.size(); ++p) {
    const int64_t n = b.per_part[p], after = K / (before * n);
    if (n < 2) {
      add("diversity_" + std::to_string(p), torch::zeros({}), 0.0);
      before *= n;
      continue;
    }
    // The samples that differ only in this part's latent (the later parts' first latent), this
    // part's nodes, future frames: Bh * before groups of n.
    torch::Tensor rows = torch::empty({Bh * before, n}, torch::kLong);
    int64_t* r = rows.data_ptr<int64_t>();
    for (int64_t h = 0; h < Bh; ++h)
      for (int64_t e = 0; e < before; ++e)
        for (int64_t i = 0; i < n; ++i) *r++ = h * K + (e * n + i) * after;
    const torch::Tensor d = GroupL1Distances(b.pred, rows, b.part_nodes[p], b.t_his);  // [G, n, n]
    const torch::Tensor upper = torch::triu(torch::ones({n, n}, torch::kBool), 1);
    const torch::Tensor pairs = d.masked_select(upper.unsqueeze(0).expand_as(d));
    add("diversity_" + std::to_string(p), torch::exp(-pairs / w.diversity_scale[p]).mean(),
        w.diversity[p]);
    before *= n;
  }

  add("best_of_many", std::get<0>(errors.future.min(1)).mean(), w.best_of_many);

  if (b.pseudo.defined() && b.pseudo.size(1) > 0 && b.pseudo_mask.sum().item<float>() > 0) {
    const int64_t M = b.pseudo.size(1), D = (T - b.t_his) * N * 3;
    // [Bh, M, K]: every pseudo future against every sample, as |p|^2 + |f|^2 - 2 p.f (one batched
    // matrix product): the direct difference would be a [Bh, M, K, t_pred, N, 3] tensor (300 MB
    // at GSPS's sizes, kept for the backward pass), and took most of the step's loss time.
    // The pseudo futures padded with zeros over the history's frames meet the whole predictions,
    // which need no copy (a slice of their future frames would) and get their gradient in one
    // piece.
    const torch::Tensor p = b.pseudo.reshape({Bh, M, D});
    const torch::Tensor padded = torch::cat({torch::zeros({Bh, M, b.t_his * N * 3}), p}, 2);
    const torch::Tensor err =
        (p.pow(2).sum(-1).unsqueeze(2) + errors.future_norm.unsqueeze(1) -
         2 * torch::bmm(padded, pred.view({Bh, K, T * N * 3}).transpose(1, 2)))
            .clamp_min(0);
    const torch::Tensor best = std::get<0>(err.min(2));  // [Bh, M]
    const torch::Tensor sum = (best * b.pseudo_mask).sum();
    add("multimodal", b.pseudo_norm > 0 ? sum * b.pseudo_norm : sum / b.pseudo_mask.sum(),
        w.multimodal);
  } else {
    add("multimodal", torch::zeros({}), 0.0);
  }

  if (hooks.prior_nll) {
    torch::Tensor frames = pred.slice(2, b.t_his + prior_offset, T, prior_step);
    if (!b.world_turn.empty()) frames = TurnedBack(frames, b);
    add("prior_nll", hooks.prior_nll(frames.reshape({-1, N, 3})), w.prior_nll);
  }
  if (hooks.angle_penalty) {
    add("angle", hooks.angle_penalty(pred.view({Bh * K, T, N, 3})), w.angle);
  }
  return out;
}

}  // namespace motionfork
