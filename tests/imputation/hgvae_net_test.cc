// The HG-VAE network: shapes for several level layouts, KL, stochastic depth, gradients.
#include "imputation/hgvae_net.h"

#include <catch2/catch.hpp>

#include "bundle/hgvae_bundle.h"

using namespace motionfork;

namespace {

HgvaeOptions Options(std::vector<HgvaeLevel> levels, int stochastic = 0,
                     bool predicted_variance = false) {
  HgvaeOptions o;
  o.levels = std::move(levels);
  o.width = 24;
  o.window = 6;
  o.stochastic_levels = stochastic;
  o.predicted_variance = predicted_variance;
  return ResolveHgvaeOptions(o, 12, 6);
}

}  // namespace

TEST_CASE("hgvae net: shapes, KL and score for 1, 2 and 4 levels, with and without classes") {
  torch::manual_seed(0);
  const std::vector<std::vector<HgvaeLevel>> layouts = {
      {{0, 8}}, {{1, 16}, {0, 8}}, {{1, 16}, {3, 8}, {6, 8}, {0, 8}}};
  for (const auto& levels : layouts) {
    for (int classes : {0, 3}) {
      for (bool predicted : {false, true}) {
        HgvaeNet net(Options(levels, 0, predicted), 12, 6, classes);
        const torch::Tensor x = torch::randn({12, 5, 6});
        torch::Tensor labels;
        if (classes > 0)
          labels = torch::zeros({5, classes}).index_fill_(1, torch::tensor({1}), 1.0);
        const HgvaeOutput o = net->forward(x, labels, LatentMode::kSample);
        CHECK(o.x_mean.sizes() == torch::IntArrayRef({12, 5, 6}));
        CHECK(o.x_logvar.sizes() == torch::IntArrayRef({12, 5, 6}));
        REQUIRE(o.z.size() == levels.size());
        for (size_t l = 0; l < levels.size(); ++l) {
          const int64_t nodes = levels[l].nodes == 0 ? 12 : levels[l].nodes;
          CHECK(o.z[l].sizes() == torch::IntArrayRef({nodes, 5, levels[l].features}));
          CHECK((o.kl_levels[l] >= -1e-4).all().item<bool>());
        }
        CHECK(o.kl.sizes() == torch::IntArrayRef({5}));
        CHECK(net->PosteriorScore(o).sizes() == torch::IntArrayRef({5}));
        CHECK(net->Generate(4, labels.defined() ? labels.slice(0, 0, 4) : torch::Tensor(), true,
                            at::make_generator<at::CPUGeneratorImpl>(1))
                  .sizes() == torch::IntArrayRef({12, 4, 6}));
      }
    }
  }
}

TEST_CASE("hgvae net: posterior means are deterministic, samples follow the generator") {
  torch::manual_seed(1);
  HgvaeNet net(Options({{1, 8}, {4, 8}, {0, 8}}), 12, 6, 0);
  net->eval();
  const torch::Tensor x = torch::randn({12, 3, 6});
  torch::NoGradGuard no_grad;
  CHECK(torch::equal(net->forward(x, {}, LatentMode::kPosteriorMean).x_mean,
                     net->forward(x, {}, LatentMode::kPosteriorMean).x_mean));
  const auto a =
      net->forward(x, {}, LatentMode::kSample, at::make_generator<at::CPUGeneratorImpl>(5)).z[1];
  const auto b =
      net->forward(x, {}, LatentMode::kSample, at::make_generator<at::CPUGeneratorImpl>(5)).z[1];
  const auto c =
      net->forward(x, {}, LatentMode::kSample, at::make_generator<at::CPUGeneratorImpl>(6)).z[1];
  CHECK(torch::equal(a, b));
  CHECK_FALSE(torch::equal(a, c));
}

TEST_CASE("hgvae net: stochastic depth turns the lower levels off") {
  torch::manual_seed(2);
  HgvaeNet net(Options({{1, 8}, {4, 8}, {0, 8}}, 1), 12, 6, 0);
  const HgvaeOutput o = net->forward(torch::randn({12, 4, 6}), {}, LatentMode::kSample);
  CHECK(o.kl_levels[0].abs().sum().item<double>() > 0);
  CHECK(o.kl_levels[1].abs().sum().item<double>() == 0);
  CHECK(o.kl_levels[2].abs().sum().item<double>() == 0);
  // Off levels take the prior's mean, whatever x is.
  CHECK(torch::equal(o.z[2], o.prior_mean[2]));
  CHECK(net->stochastic(0));
  CHECK_FALSE(net->stochastic(1));
}

TEST_CASE("hgvae net: every parameter receives a gradient from the ELBO") {
  torch::manual_seed(3);
  HgvaeNet net(Options({{1, 8}, {4, 8}, {0, 8}}), 12, 6, 2);
  // ReZero weights start at 0, which blocks the gradient of their branch: move them first.
  for (auto& p : net->named_parameters()) {
    if (p.key().find("alpha") != std::string::npos) p.value().data().fill_(0.5);
  }
  const torch::Tensor x = torch::randn({12, 8, 6});
  const torch::Tensor labels = torch::zeros({8, 2}).index_fill_(1, torch::tensor({0}), 1.0);
  const HgvaeOutput o = net->forward(x, labels, LatentMode::kSample);
  (-(HgvaeNetImpl::GaussianLogLik(x, o.x_mean, o.x_logvar) - o.kl).mean()).backward();
  for (const auto& p : net->named_parameters()) {
    INFO(p.key());
    REQUIRE(p.value().grad().defined());
    CHECK(p.value().grad().abs().sum().item<double>() > 0);
  }
}

TEST_CASE("hgvae net: the Gaussian log-likelihood matches the formula") {
  const torch::Tensor x = torch::tensor({0.5f, -1.0f}).view({2, 1, 1});
  const torch::Tensor mean = torch::tensor({0.0f, 0.0f}).view({2, 1, 1});
  const torch::Tensor logvar = torch::tensor({0.0f, std::log(4.0f)}).view({2, 1, 1});
  const double expected =
      -0.5 * (std::log(2 * M_PI) + 0.25) - 0.5 * (std::log(2 * M_PI) + std::log(4.0) + 0.25);
  CHECK(HgvaeNetImpl::GaussianLogLik(x, mean, logvar).item<double>() ==
        Approx(expected).epsilon(1e-6));
}
