#include "torch_catch.h"

#include "generator/losses.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

// The term named `name` of `terms`.
torch::Tensor Term(const LossTerms& terms, const std::string& name) {
  for (const auto& [n, v] : terms.terms)
    if (n == name) return v;
  FAIL("no loss term " << name);
  return {};
}

}  // namespace

TEST_CASE("losses: pseudo multimodal term equals the direct squared distances, values and gradients") {
  PinThreads(1);
  torch::manual_seed(3);
  const int64_t Bh = 2, K = 6, M = 3, t_his = 4, T = 10, N = 5;
  LossBatch b;
  const torch::Tensor pred = (torch::randn({Bh * K, T, N, 3}) * 0.3).requires_grad_(true);
  b.pred = pred;
  b.truth = torch::randn({Bh, T, N, 3}) * 0.3;
  b.pseudo = torch::randn({Bh, M, T - t_his, N, 3}) * 0.3;
  b.pseudo_mask = torch::tensor({1.0f, 1.0f, 0.0f, 1.0f, 0.0f, 0.0f}).view({Bh, M});
  b.per_part = {2, 3};
  b.part_nodes = {{0, 1}, {2, 3, 4}};
  b.node_parents = {-1, 0, -1, 2, 3};
  b.t_his = t_his;
  LossWeights w;
  w.diversity = {1, 1};
  w.diversity_scale = {1, 1};
  const LossTerms terms = ComputeLosses(b, w, LossHooks{}, 0, 1);
  const torch::Tensor got = Term(terms, "multimodal");
  const torch::Tensor grad_got = torch::autograd::grad({got}, {pred})[0];

  // Direct: every pseudo future minus every sample, squared, summed over frames, nodes and axes;
  // the best sample per pseudo future, averaged over the pseudo futures that exist.
  const torch::Tensor future = pred.view({Bh, K, T, N, 3}).slice(2, t_his);
  const torch::Tensor err = (future.unsqueeze(1) - b.pseudo.unsqueeze(2)).pow(2).sum({-1, -2, -3});  // [Bh, M, K]
  const torch::Tensor best = std::get<0>(err.min(2));
  const torch::Tensor want = (best * b.pseudo_mask).sum() / b.pseudo_mask.sum();
  const torch::Tensor grad_want = torch::autograd::grad({want}, {pred})[0];
  CHECK(got.item<double>() == Approx(want.item<double>()).epsilon(1e-5));
  CHECK(torch::allclose(grad_got, grad_want, 1e-4, 1e-5));
  CHECK(grad_got.abs().sum().item<double>() > 0);
}
