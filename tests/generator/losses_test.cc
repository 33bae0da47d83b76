#include "generator/training/losses.h"

#include "torch_catch.h"
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

// The two tests' batch: Bh = 2 histories, samples nested 2 x 3 over two parts of 5 nodes, t_his 4.
LossBatch SmallBatch(int64_t T) {
  LossBatch b;
  b.truth = torch::randn({2, T, 5, 3}) * 0.3;
  b.per_part = {2, 3};
  b.part_nodes = {{0, 1}, {2, 3, 4}};
  b.node_parents = {-1, 0, -1, 2, 3};
  b.t_his = 4;
  return b;
}

LossWeights UnitDiversity() {
  LossWeights w;
  w.diversity = {1, 1};
  w.diversity_scale = {1, 1};
  return w;
}

}  // namespace

TEST_CASE(
    "losses: pseudo multimodal term equals the direct squared distances, values and gradients") {
  PinThreads(1);
  torch::manual_seed(3);
  const int64_t Bh = 2, K = 6, M = 3, t_his = 4, T = 10, N = 5;
  const torch::Tensor pred = (torch::randn({Bh * K, T, N, 3}) * 0.3).requires_grad_(true);
  LossBatch b = SmallBatch(T);
  b.pred = pred;
  b.pseudo = torch::randn({Bh, M, T - t_his, N, 3}) * 0.3;
  b.pseudo_mask = torch::tensor({1.0f, 1.0f, 0.0f, 1.0f, 0.0f, 0.0f}).view({Bh, M});
  const LossWeights w = UnitDiversity();
  const LossTerms terms = ComputeLosses(b, w, LossHooks{}, 0, 1);
  const torch::Tensor got = Term(terms, "multimodal");
  const torch::Tensor grad_got = torch::autograd::grad({got}, {pred})[0];

  // Direct: every pseudo future minus every sample, squared, summed over frames, nodes and axes;
  // the best sample per pseudo future, averaged over the pseudo futures that exist.
  const torch::Tensor future = pred.view({Bh, K, T, N, 3}).slice(2, t_his);
  const torch::Tensor err =
      (future.unsqueeze(1) - b.pseudo.unsqueeze(2)).pow(2).sum({-1, -2, -3});  // [Bh, M, K]
  const torch::Tensor best = std::get<0>(err.min(2));
  const torch::Tensor want = (best * b.pseudo_mask).sum() / b.pseudo_mask.sum();
  const torch::Tensor grad_want = torch::autograd::grad({want}, {pred})[0];
  CHECK(got.item<double>() == Approx(want.item<double>()).epsilon(1e-5));
  CHECK(torch::allclose(grad_got, grad_want, 1e-4, 1e-5));
  CHECK(grad_got.abs().sum().item<double>() > 0);
}

TEST_CASE("losses: fused pose errors equal GSPS's formulas in LibTorch ops, values and gradients") {
  PinThreads(1);
  torch::manual_seed(4);
  const int64_t Bh = 2, K = 6, t_his = 4, T = 10, N = 5;
  torch::Tensor pred0 = torch::randn({Bh * K, T, N, 3}) * 0.3;
  pred0[0][2][3].zero_();  // a zero-length bone from node 2 (hangs from the origin) ...
  pred0[1][5][4] = pred0[1][5][3].clone();  // ... and one between nodes 3 and 4: no NaN gradient
  pred0[3][6] = pred0[0][6].clone();  // samples 0 and 3 (part 0's diversity pair) equal in frame 6
  LossBatch b = SmallBatch(T);
  const LossWeights w = UnitDiversity();
  torch::Tensor prior_frames;
  LossHooks hooks;
  hooks.prior_nll = [&](const torch::Tensor& poses) {
    prior_frames = poses;
    return poses.pow(2).mean();
  };
  const torch::Tensor pred = pred0.clone().requires_grad_(true);
  b.pred = pred;
  const LossTerms terms = ComputeLosses(b, w, hooks, 1, 2);

  // Reference: the direct LibTorch formulas.
  const torch::Tensor r_pred = pred0.clone().requires_grad_(true);
  const torch::Tensor p5 = r_pred.view({Bh, K, T, N, 3});
  const torch::Tensor past = p5.slice(2, 0, t_his), future = p5.slice(2, t_his);
  const torch::Tensor r_past =
      (past - b.truth.slice(1, 0, t_his).unsqueeze(1)).pow(2).sum({-1, -2}).mean(-1).mean();
  const torch::Tensor parent_index = torch::tensor(std::vector<int64_t>{0, 0, 2, 2, 3});
  const torch::Tensor from_root = torch::tensor(std::vector<float>{1, 0, 1, 0, 0}).view({N, 1});
  auto lengths = [&](const torch::Tensor& poses) {
    return (poses - poses.index_select(-2, parent_index) * (1 - from_root)).norm(2, -1);
  };
  const torch::Tensor truth_len = lengths(b.truth.select(1, t_his - 1));
  const torch::Tensor r_limb = (lengths(p5) - truth_len.view({Bh, 1, 1, N})).pow(2).sum(-1).mean();
  const torch::Tensor r_best =
      std::get<0>((future - b.truth.slice(1, t_his).unsqueeze(1)).pow(2).sum({-1, -2, -3}).min(1))
          .mean();
  const torch::Tensor r_frames = future.slice(2, 1, T - t_his, 2).reshape({-1, N, 3});
  // Diversity, both parts: exp(-L1 distance) over the pairs of samples that differ only in the
  // part's latent, the part's nodes, future frames (cdist, as GSPS's pdist). Part 0's groups are
  // samples {0, 3} and {6, 9} (part 1's first latent), part 1's {0, 1, 2}, {3, 4, 5}, ...
  const torch::Tensor f7 = future.reshape({Bh, 2, 3, T - t_his, N, 3});
  const torch::Tensor x0 = f7.select(2, 0)
                               .index_select(3, torch::tensor(std::vector<int64_t>{0, 1}))
                               .reshape({Bh, 2, -1});
  const torch::Tensor x1 =
      f7.index_select(4, torch::tensor(std::vector<int64_t>{2, 3, 4})).reshape({Bh * 2, 3, -1});
  auto diversity = [](const torch::Tensor& x) {
    const int64_t n = x.size(1);
    const torch::Tensor d = torch::cdist(x, x, 1.0);
    const torch::Tensor upper = torch::triu(torch::ones({n, n}, torch::kBool), 1);
    return torch::exp(-d.masked_select(upper.unsqueeze(0).expand_as(d))).mean();
  };
  const std::vector<std::pair<std::string, torch::Tensor>> reference = {
      {"past_reconstruction", r_past},
      {"limb_length", r_limb},
      {"best_of_many", r_best},
      {"diversity_0", diversity(x0)},
      {"diversity_1", diversity(x1)}};
  for (const auto& [name, want] : reference) {
    INFO(name);
    const torch::Tensor got = Term(terms, name);
    CHECK(torch::allclose(got, want, 1e-5, 1e-6));
    const torch::Tensor g_got = torch::autograd::grad({got}, {pred}, {}, /*retain_graph=*/true)[0];
    const torch::Tensor g_want =
        torch::autograd::grad({want}, {r_pred}, {}, /*retain_graph=*/true)[0];
    CHECK(torch::isfinite(g_got).all().item<bool>());
    CHECK(g_got.abs().sum().item<double>() > 0);
    CHECK(torch::allclose(g_got, g_want, 1e-4, 1e-6));
  }
  REQUIRE(prior_frames.defined());
  CHECK(torch::equal(prior_frames, r_frames));
}

TEST_CASE("losses: in the body's frame the prior scores the poses turned back to the data's axes") {
  PinThreads(1);
  torch::manual_seed(5);
  const int64_t Bh = 2, K = 6, T = 10, N = 5;
  const torch::Tensor world = torch::randn({Bh * K, T, N, 3}) * 0.3;
  // Each history's window turned about y (ground axes x = 0, z = 2) by its own angle, as
  // training turns a window into its body frame; world_turn takes it back.
  const std::vector<double> turn = {0.8, -2.1};
  torch::Tensor body = world.clone();
  for (int64_t h = 0; h < Bh; ++h) {
    const double c = std::cos(turn[h]), s = std::sin(turn[h]);
    const torch::Tensor x = world.slice(0, h * K, (h + 1) * K).select(-1, 0);
    const torch::Tensor z = world.slice(0, h * K, (h + 1) * K).select(-1, 2);
    body.slice(0, h * K, (h + 1) * K).select(-1, 0).copy_(c * x - s * z);
    body.slice(0, h * K, (h + 1) * K).select(-1, 2).copy_(s * x + c * z);
  }
  auto prior_input = [&](const torch::Tensor& pred, const std::vector<double>& world_turn) {
    LossBatch b = SmallBatch(T);
    b.pred = pred.clone().requires_grad_(true);
    b.world_turn = world_turn;
    torch::Tensor seen;
    LossHooks hooks;
    hooks.prior_nll = [&](const torch::Tensor& poses) {
      seen = poses.detach().clone();
      return poses.pow(2).mean();
    };
    const LossTerms terms = ComputeLosses(b, UnitDiversity(), hooks, 0, 1);
    CHECK(
        torch::autograd::grad({Term(terms, "prior_nll")}, {b.pred})[0].abs().sum().item<double>() >
        0);
    return seen;
  };
  const torch::Tensor want = prior_input(world, {});
  const torch::Tensor got = prior_input(body, {-turn[0], -turn[1]});
  CHECK(torch::allclose(got, want, 1e-5, 1e-5));
  CHECK_FALSE(torch::allclose(prior_input(body, {}), want, 1e-3, 1e-3));
  CHECK_THROWS_WITH(prior_input(body, {0.5}), Catch::Contains("expected 2 turns, got 1"));
}
