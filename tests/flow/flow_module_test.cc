// Invariants of the flow network: invertibility, exact log-det (autograd and finite-difference
// Jacobians), orthogonality of Q (two constructions cross-checked), and the differentiable
// limb-direction transform against core's.
#include "flow/flow_module.h"

#include <cmath>

#include "core/limbs.h"
#include "flow/catch_torch.h"
#include "test_support.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

constexpr int kDim = 48;

PoseFlow MakeFlow(uint64_t seed, int layers = 3) {
  FlowOptions o;
  o.num_layers = layers;
  PoseFlow flow(kDim, o);
  flow->Initialize(seed);
  return flow;
}

// Random unit limb directions: [n, 48].
torch::Tensor RandomDirections(int64_t n, uint64_t seed) {
  torch::manual_seed(seed);
  torch::Tensor d = torch::randn({n, kDim / 3, 3});
  return (d / d.norm(2, -1, true)).reshape({n, kDim});
}

// A few Adam steps of NLL on synthetic directions, so tests also see trained (not initial) weights.
void TrainSteps(PoseFlow& flow, int steps) {
  torch::optim::Adam adam(flow->parameters(), torch::optim::AdamOptions(1e-2).weight_decay(1e-3));
  const torch::Tensor data = RandomDirections(512, 3) * 0.5 + 0.3;
  for (int s = 0; s < steps; ++s) {
    const torch::Tensor loss = -flow->log_prob(data).mean();
    adam.zero_grad();
    loss.backward();
    adam.step();
  }
}

double MaxAbs(const torch::Tensor& t) { return t.abs().max().item<double>(); }

}  // namespace

TEST_CASE("inverse(forward(x)) == x to 1e-4 in float32, before and after training") {
  PinThreads(1);
  PoseFlow flow = MakeFlow(11);
  torch::NoGradGuard no_grad;
  for (int round = 0; round < 2; ++round) {
    for (uint64_t seed : {1u, 2u, 3u}) {
      const torch::Tensor x = RandomDirections(2000, seed);
      const torch::Tensor gauss = torch::randn({2000, kDim}) * 2.0;  // off the unit-limb manifold
      for (const torch::Tensor& in : {x, gauss}) {
        const torch::Tensor back = flow->inverse(flow->forward(in).first);
        INFO("round " << round << " seed " << seed);
        CHECK(MaxAbs(back - in) < 1e-4);
      }
      // And the other way round: forward(inverse(z)) == z.
      const torch::Tensor z = torch::randn({500, kDim});
      CHECK(MaxAbs(flow->forward(flow->inverse(z)).first - z) < 1e-4);
    }
    if (round == 0) {
      torch::AutoGradMode grad(true);
      TrainSteps(flow, 30);
    }
  }
}

TEST_CASE("log-det equals log|det J| of the autograd Jacobian and of central differences") {
  PinThreads(1);
  PoseFlow flow = MakeFlow(5);
  TrainSteps(flow, 20);
  flow->to(torch::kFloat64);
  for (uint64_t seed : {21u, 22u, 23u, 24u}) {
    const torch::Tensor x0 = RandomDirections(1, seed).to(torch::kFloat64);
    // Autograd Jacobian, one row per output.
    torch::Tensor x = x0.clone().requires_grad_(true);
    const auto [z, log_det] = flow->forward(x);
    torch::Tensor jac = torch::zeros({kDim, kDim}, torch::kFloat64);
    for (int i = 0; i < kDim; ++i) {
      const auto g = torch::autograd::grad({z[0][i]}, {x}, {}, /*retain_graph=*/true);
      jac[i] = g[0][0];
    }
    const double autograd_logdet = std::get<1>(torch::linalg_slogdet(jac)).item<double>();
    // Central differences (no input is near a PReLU kink for these seeds: checked by the match).
    torch::NoGradGuard no_grad;
    const double h = 1e-6;
    torch::Tensor fd = torch::zeros({kDim, kDim}, torch::kFloat64);
    for (int j = 0; j < kDim; ++j) {
      torch::Tensor xp = x0.clone(), xm = x0.clone();
      xp[0][j] += h;
      xm[0][j] -= h;
      fd.select(1, j).copy_((flow->forward(xp).first[0] - flow->forward(xm).first[0]) / (2 * h));
    }
    const double fd_logdet = std::get<1>(torch::linalg_slogdet(fd)).item<double>();
    const double model = log_det.item<double>();
    INFO("seed " << seed << ": model " << model << ", autograd " << autograd_logdet << ", fd "
                 << fd_logdet);
    CHECK(std::abs(model - autograd_logdet) < 1e-8);
    CHECK(std::abs(model - fd_logdet) < 1e-5);
  }
}

TEST_CASE(
    "Q is orthogonal to 1e-5 after training, and compact WY equals the reflections applied in "
    "turn") {
  PinThreads(1);
  PoseFlow flow = MakeFlow(9);
  TrainSteps(flow, 200);
  torch::NoGradGuard no_grad;
  for (int l = 0; l < flow->num_layers(); ++l) {
    const torch::Tensor q = flow->layer(l)->Orthogonal();
    const torch::Tensor eye = torch::eye(kDim, torch::kFloat64);
    CHECK(MaxAbs(q.t().mm(q) - eye) < 1e-5);
    CHECK(MaxAbs(q.to(torch::kFloat32).t().mm(q.to(torch::kFloat32)) - eye.to(torch::kFloat32)) <
          1e-5);
    CHECK(MaxAbs(q - flow->layer(l)->OrthogonalSequential()) < 1e-10);
    // W W^-1 = I and log|det W| = sum of the log-diagonal.
    const torch::Tensor w = flow->layer(l)->Weight();
    CHECK(MaxAbs(w.mm(flow->layer(l)->InverseWeight()) - eye) < 1e-9);
    CHECK(std::get<1>(torch::linalg_slogdet(w)).item<double>() ==
          Approx(flow->layer(l)->LogAbsDet().item<double>()).margin(1e-9));
  }
}

TEST_CASE("log_prob integrates the standard normal: a 1-layer flow at identity is N(0, I)") {
  FlowOptions o;
  o.num_layers = 1;
  o.num_reflections = 1;
  PoseFlow flow(3, o);
  torch::NoGradGuard no_grad;
  flow->Initialize(1);
  flow->layer(0)->reflections.fill_(0);
  flow->layer(0)->reflections[0][0] = 1;  // Q = diag(-1, 1, 1): |det| = 1, and |z| unchanged
  flow->layer(0)->r_log_diag.zero_();
  flow->layer(0)->r_upper.zero_();
  flow->layer(0)->bias.zero_();
  const torch::Tensor x = torch::tensor({{0.0f, 0.0f, 0.0f}, {1.0f, 2.0f, -1.0f}});
  const torch::Tensor lp = flow->log_prob(x);
  const double c = -1.5 * std::log(2 * M_PI);
  CHECK(lp[0].item<double>() == Approx(c).margin(1e-6));
  CHECK(lp[1].item<double>() == Approx(c - 3.0).margin(1e-5));
}

TEST_CASE("training steps lower the NLL and keep every parameter finite") {
  PinThreads(1);
  PoseFlow flow = MakeFlow(4);
  const torch::Tensor data = RandomDirections(512, 3) * 0.5 + 0.3;
  double before;
  {
    torch::NoGradGuard g;
    before = -flow->log_prob(data).mean().item<double>();
  }
  TrainSteps(flow, 100);
  torch::NoGradGuard g;
  const double after = -flow->log_prob(data).mean().item<double>();
  WARN("synthetic NLL: " << before << " -> " << after << " nats per pose after 100 steps");
  CHECK(after < before - 10);
  for (const auto& p : flow->parameters()) CHECK(torch::isfinite(p).all().item<bool>());
}

TEST_CASE("LimbDirections (differentiable) equals ToLimbs, and gives finite gradients") {
  const Motion m = testing::MakeWalkingMotion(10);
  const Limbs limbs = ToLimbs(m);
  torch::Tensor pos =
      torch::from_blob(const_cast<float*>(m.positions().data()), {10, 17, 3}, torch::kFloat32)
          .clone()
          .requires_grad_(true);
  const torch::Tensor d = LimbDirections(pos, m.skeleton().parents());
  REQUIRE(d.sizes() == torch::IntArrayRef({10, 48}));
  const torch::Tensor expected =
      torch::from_blob(const_cast<float*>(limbs.directions.data()), {10, 48}, torch::kFloat32);
  CHECK(MaxAbs(d.detach() - expected) < 1e-5);
  // A collapsed bone (joint on its parent) still gives finite gradients.
  torch::Tensor collapsed = pos.detach().clone();
  collapsed[0][2] = collapsed[0][1];
  collapsed.requires_grad_(true);
  LimbDirections(collapsed, m.skeleton().parents()).sum().backward();
  CHECK(torch::isfinite(collapsed.grad()).all().item<bool>());
  CHECK_THROWS_AS(LimbDirections(torch::zeros({4, 16, 3}), m.skeleton().parents()),
                  std::invalid_argument);
}

TEST_CASE("options are validated with the field's name") {
  FlowOptions o;
  o.num_layers = 0;
  CHECK_THROWS_WITH(PoseFlow(48, o), Catch::Contains("model.layers"));
  o = FlowOptions();
  o.prelu_init = -0.1;
  CHECK_THROWS_WITH(PoseFlow(48, o), Catch::Contains("model.prelu_init"));
  o = FlowOptions();
  o.num_reflections = 49;
  CHECK_THROWS_WITH(PoseFlow(48, o), Catch::Contains("model.reflections"));
  const PoseFlow flow = MakeFlow(1);
  CHECK_THROWS_AS(flow->forward(torch::zeros({2, 47})), std::invalid_argument);
  CHECK(flow->NumParameters() == 3 * (48 * 48 + 48 + 48 * 47 / 2 + 48) + 2);
}

TEST_CASE("the frozen-prior fast path gives the same log-probs and pose gradients as autograd") {
  PinThreads(1);
  PoseFlow flow = MakeFlow(13);
  TrainSteps(flow, 10);
  flow->to(torch::kFloat64);
  const torch::Tensor x0 = RandomDirections(300, 31).to(torch::kFloat64);
  torch::Tensor a = x0.clone().requires_grad_(true);
  const torch::Tensor lp_a = flow->log_prob(a);  // parameters trainable: plain autograd
  (lp_a * torch::linspace(0.5, 2.0, 300, torch::kFloat64)).sum().backward();
  for (auto& p : flow->parameters()) p.requires_grad_(false);
  REQUIRE_FALSE(flow->AnyParameterRequiresGrad());
  torch::Tensor b = x0.clone().requires_grad_(true);
  const torch::Tensor lp_b = flow->log_prob(b);  // frozen: the fused path
  (lp_b * torch::linspace(0.5, 2.0, 300, torch::kFloat64)).sum().backward();
  CHECK(MaxAbs(lp_a.detach() - lp_b.detach()) < 1e-10);
  CHECK(MaxAbs(a.grad() - b.grad()) < 1e-9);
  CHECK(MaxAbs(b.grad()) > 1e-3);
}

TEST_CASE("fused CPU LimbDirections equals the tensor-op version, values and gradients") {
  const Motion m = testing::MakeWalkingMotion(40);
  const std::vector<int>& parents = m.skeleton().parents();
  for (auto dtype : {torch::kFloat32, torch::kFloat64}) {
    const torch::Tensor base =
        torch::from_blob(const_cast<float*>(m.positions().data()), {4, 10, 17, 3}, torch::kFloat32)
            .to(dtype);
    torch::Tensor p1 = base.clone().requires_grad_(true), p2 = base.clone().requires_grad_(true);
    const torch::Tensor d1 = LimbDirections(p1, parents), d2 = LimbDirectionsReference(p2, parents);
    REQUIRE(d1.sizes() == torch::IntArrayRef({4, 10, 48}));
    const torch::Tensor w = torch::randn({4, 10, 48}).to(dtype);
    (d1 * w).sum().backward();
    (d2 * w).sum().backward();
    const double tol = dtype == torch::kFloat32 ? 1e-5 : 1e-12;
    CHECK(MaxAbs(d1.detach() - d2.detach()) < tol);
    CHECK(MaxAbs(p1.grad() - p2.grad()) < 100 * tol);
  }
  // Central differences on the fused version (float64).
  torch::Tensor p = torch::randn({2, 17, 3}, torch::kFloat64).requires_grad_(true);
  const torch::Tensor w = torch::randn({2, 48}, torch::kFloat64);
  (LimbDirections(p, parents) * w).sum().backward();
  torch::NoGradGuard no_grad;
  const double h = 1e-6;
  double worst = 0;
  for (int i = 0; i < 2 * 17 * 3; ++i) {
    torch::Tensor pp = p.detach().clone(), pm = p.detach().clone();
    pp.view({-1})[i] += h;
    pm.view({-1})[i] -= h;
    const double fd =
        ((LimbDirections(pp, parents) - LimbDirections(pm, parents)) * w).sum().item<double>() /
        (2 * h);
    worst = std::max(worst, std::abs(fd - p.grad().view({-1})[i].item<double>()));
  }
  CHECK(worst < 1e-6);
}

TEST_CASE("LimbDirectionsRootRelative (root omitted, at the origin) equals LimbDirections") {
  const Motion m = testing::MakeWalkingMotion(12);
  const std::vector<int>& parents = m.skeleton().parents();
  const Motion rel = RootRelative(m);
  const torch::Tensor full =
      torch::from_blob(const_cast<float*>(rel.positions().data()), {12, 17, 3}, torch::kFloat32)
          .to(torch::kFloat64);
  torch::Tensor a = full.clone().requires_grad_(true);
  torch::Tensor b = full.slice(1, 1, 17).clone().requires_grad_(true);
  const torch::Tensor da = LimbDirections(a, parents), db = LimbDirectionsRootRelative(b, parents);
  CHECK(MaxAbs(da.detach() - db.detach()) < 1e-12);
  const torch::Tensor w = torch::randn({12, 48}, torch::kFloat64);
  (da * w).sum().backward();
  (db * w).sum().backward();
  CHECK(MaxAbs(a.grad().slice(1, 1, 17) - b.grad()) < 1e-12);
  CHECK_THROWS_WITH(LimbDirectionsRootRelative(a.detach(), parents),
                    Catch::Contains("root omitted"));
  // Through the frozen prior, as the generator uses it.
  PoseFlow flow = MakeFlow(2);
  flow->Freeze();
  flow->to(torch::kFloat64);
  torch::Tensor c = full.slice(1, 1, 17).clone().requires_grad_(true);
  (-flow->log_prob(LimbDirectionsRootRelative(c, parents)).mean()).backward();
  CHECK(torch::isfinite(c.grad()).all().item<bool>());
}
