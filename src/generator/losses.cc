#include "generator/losses.h"

#include <stdexcept>

namespace motionfork {

namespace {

// Bone lengths [.., N] of poses [.., N, 3]; a node whose parent is the root hangs from the origin.
torch::Tensor BoneLengths(const torch::Tensor& poses, const torch::Tensor& parent_index,
                          const torch::Tensor& from_root) {
  const torch::Tensor parents = poses.index_select(-2, parent_index) * (1 - from_root);
  return (poses - parents).norm(2, -1);
}

// Reductions as in GSPS's released training code, which its loss weights are tuned for:
// squared distance summed over the whole pose (nodes x 3), then
//   PoseSquaredError: averaged over frames (history reconstruction);
//   SequenceSquaredError: summed over frames too (best-of-many, pseudo multimodal futures).
// a: [.., T, N, 3], b broadcastable.
torch::Tensor PoseSquaredError(const torch::Tensor& a, const torch::Tensor& b) {
  return (a - b).pow(2).sum({-1, -2}).mean(-1);
}

torch::Tensor SequenceSquaredError(const torch::Tensor& a, const torch::Tensor& b) {
  return (a - b).pow(2).sum({-1, -2, -3});
}

}  // namespace

LossTerms ComputeLosses(const LossBatch& b, const LossWeights& w, const LossHooks& hooks,
                        int64_t prior_offset, int64_t prior_step) {
  const int64_t Bh = b.truth.size(0), T = b.truth.size(1), N = b.truth.size(2);
  int64_t K = 1;
  for (int64_t n : b.per_part) K *= n;
  if (b.pred.size(0) != Bh * K) {
    throw std::invalid_argument("losses: expected " + std::to_string(Bh * K) + " predictions, got " +
                                std::to_string(b.pred.size(0)));
  }
  const torch::Tensor pred = b.pred.view({Bh, K, T, N, 3});
  const torch::Tensor past = pred.slice(2, 0, b.t_his), future = pred.slice(2, b.t_his);
  const torch::Tensor truth_past = b.truth.slice(1, 0, b.t_his).unsqueeze(1);
  const torch::Tensor truth_future = b.truth.slice(1, b.t_his).unsqueeze(1);
  LossTerms out;
  auto add = [&](const std::string& name, const torch::Tensor& value, double weight) {
    out.terms.emplace_back(name, value);
    out.total = out.total.defined() ? out.total + weight * value : weight * value;
  };

  add("past_reconstruction", PoseSquaredError(past, truth_past).mean(), w.past_reconstruction);

  std::vector<int64_t> parents = b.node_parents;
  std::vector<float> root_flag(N);
  for (int64_t n = 0; n < N; ++n) {
    root_flag[n] = parents[n] < 0 ? 1.0f : 0.0f;
    if (parents[n] < 0) parents[n] = n;
  }
  const torch::Tensor parent_index = torch::tensor(parents, torch::kLong);
  const torch::Tensor from_root = torch::tensor(root_flag).view({N, 1});
  const torch::Tensor truth_len = BoneLengths(b.truth.select(1, b.t_his - 1), parent_index, from_root);  // [Bh, N]
  const torch::Tensor pred_len = BoneLengths(pred, parent_index, from_root);                             // [Bh, K, T, N]
  // Squared bone-length errors summed over the bones of a pose, averaged over poses (GSPS).
  add("limb_length", (pred_len - truth_len.view({Bh, 1, 1, N})).pow(2).sum(-1).mean(), w.limb_length);

  // Diversity of each part among the samples that differ only in its own latent.
  int64_t before = 1;
  for (size_t p = 0; p < b.per_part.size(); ++p) {
    const int64_t n = b.per_part[p], after = K / (before * n);
    if (n < 2) {
      add("diversity_" + std::to_string(p), torch::zeros({}), 0.0);
      before *= n;
      continue;
    }
    const torch::Tensor nodes = torch::tensor(b.part_nodes[p], torch::kLong);
    const torch::Tensor x = future.reshape({Bh, before, n, after, T - b.t_his, N, 3})
                                .select(3, 0)
                                .index_select(4, nodes)
                                .reshape({Bh * before, n, -1});
    const torch::Tensor d = torch::cdist(x, x, 1.0);  // [G, n, n]
    const torch::Tensor upper = torch::triu(torch::ones({n, n}, torch::kBool), 1);
    const torch::Tensor pairs = d.masked_select(upper.unsqueeze(0).expand_as(d));
    add("diversity_" + std::to_string(p), torch::exp(-pairs / w.diversity_scale[p]).mean(), w.diversity[p]);
    before *= n;
  }

  const torch::Tensor future_err = SequenceSquaredError(future, truth_future);  // [Bh, K]
  add("best_of_many", std::get<0>(future_err.min(1)).mean(), w.best_of_many);

  if (b.pseudo.defined() && b.pseudo.size(1) > 0 && b.pseudo_mask.sum().item<float>() > 0) {
    const int64_t M = b.pseudo.size(1), D = (T - b.t_his) * N * 3;
    // [Bh, M, K]: every pseudo future against every sample, as |p|^2 + |f|^2 - 2 p.f (one batched
    // matrix product): the direct difference would be a [Bh, M, K, t_pred, N, 3] tensor (300 MB
    // at GSPS's sizes, kept for the backward pass), and took most of the step's loss time.
    const torch::Tensor f = future.reshape({Bh, K, D}), p = b.pseudo.reshape({Bh, M, D});
    const torch::Tensor err = (p.pow(2).sum(-1).unsqueeze(2) + f.pow(2).sum(-1).unsqueeze(1) -
                               2 * torch::bmm(p, f.transpose(1, 2)))
                                  .clamp_min(0);
    const torch::Tensor best = std::get<0>(err.min(2));  // [Bh, M]
    add("multimodal", (best * b.pseudo_mask).sum() / b.pseudo_mask.sum(), w.multimodal);
  } else {
    add("multimodal", torch::zeros({}), 0.0);
  }

  if (hooks.prior_nll) {
    const torch::Tensor frames = future.slice(2, prior_offset, T - b.t_his, prior_step);
    add("prior_nll", hooks.prior_nll(frames.reshape({-1, N, 3})), w.prior_nll);
  }
  if (hooks.angle_penalty) {
    add("angle", hooks.angle_penalty(pred.view({Bh * K, T, N, 3})), w.angle);
  }
  return out;
}

}  // namespace motionfork
