// GSPS training losses (LibTorch). Poses are root-relative without the root: [.., N, 3], metres.
#pragma once

#include <torch/torch.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "generator/model/training_options.h"

namespace motionfork {

struct LossBatch {
  torch::Tensor pred;             // [Bh * K, T, N, 3], K = prod(per_part), nested sample order
  torch::Tensor truth;            // [Bh, T, N, 3]
  torch::Tensor pseudo;           // [Bh, M, t_pred, N, 3] pseudo multimodal futures (M may be 0)
  torch::Tensor pseudo_mask;      // [Bh, M] 1 where a pseudo future exists
  std::vector<int64_t> per_part;  // nested samples per part
  std::vector<std::vector<int64_t>> part_nodes;  // nodes of each part
  std::vector<int64_t> node_parents;             // parent node per node, -1 = the root (origin)
  int64_t t_his = 0;
  // 0: the multimodal term is the mean over this batch's pseudo futures. > 0: the batch is one
  // worker's share of a data-parallel batch and the term is its sum times this, B / (Bs * C) for
  // a batch of B histories, a share of Bs and C pseudo futures in the whole batch, so that the
  // shares' terms weighted by Bs / B add up to the whole batch's mean.
  double pseudo_norm = 0;
  // Training in the body's frame (generator.body_frame): per history, the turn about up (radians,
  // core/heading.h's sense) that takes its window back to the data's own axes, and the ground
  // axes (a, b) it turns; the prior, trained on the data as it was recorded, scores the poses so
  // turned back. Empty: the poses are in the data's axes already.
  std::vector<double> world_turn;
  int ground_a = 0, ground_b = 2;
};

// Optional terms from other modules: scalar tensors from predicted poses.
struct LossHooks {
  std::function<torch::Tensor(const torch::Tensor& poses /*[M, N, 3]*/)> prior_nll;
  std::function<torch::Tensor(const torch::Tensor& poses /*[B, T, N, 3]*/)> angle_penalty;
};

struct LossTerms {
  std::vector<std::pair<std::string, torch::Tensor>> terms;  // unweighted, in GSPS order
  torch::Tensor total;                                       // weighted sum
};

// prior_offset: first predicted frame scored by the prior (then every `prior_step`).
LossTerms ComputeLosses(const LossBatch& batch, const LossWeights& weights, const LossHooks& hooks,
                        int64_t prior_offset, int64_t prior_step);

}  // namespace motionfork
