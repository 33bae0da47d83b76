// The Motion-DVAE network and its objectives: shapes, KL formulas, gradients.
#include "bundle/dvae_bundle.h"
#include "denoise/dvae_objective.h"
#include "test_support.h"
#include "tiny_dvae.h"
#include "torch_catch.h"

using namespace motionfork;

namespace {

DvaeManifest TinyManifest() {
  const DvaeTrainConfig cfg = testing::TinyDvaeConfig(1, 1);
  DvaeManifest m = testing::TinyDvaeBase(cfg);
  m.model = cfg.model;
  const size_t F = 3 * m.skeleton.joint_names.size();
  m.mean.assign(F, 0.0);
  m.std.assign(F, 0.5);
  return m;
}

}  // namespace

TEST_CASE("dvae net: shapes of a pass, the initial state, the noise and generated sequences") {
  torch::manual_seed(0);
  const DvaeManifest m = TinyManifest();
  DvaeNet net = BuildDvaeNet(m);
  const int64_t B = 3, T1 = 10, F = DvaeValues(m);
  const torch::Tensor x = torch::randn({B, T1, F});
  at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(1);
  const DvaePass p = net->Run(x, x.select(1, 0), true, gen);
  CHECK(p.mean.sizes() == torch::IntArrayRef({B, T1 - 1, F}));
  CHECK(p.hidden.sizes() == torch::IntArrayRef({B, T1, 32}));
  CHECK(p.z.sizes() == torch::IntArrayRef({B, T1 - 1, 8}));
  CHECK(p.prior_mean.sizes() == p.post_mean.sizes());
  CHECK(p.kl.sizes() == torch::IntArrayRef({B}));
  CHECK((p.kl >= 0).all().item<bool>());
  const auto [m0, lv0] = net->InitialState(x);
  CHECK(m0.sizes() == torch::IntArrayRef({B, F}));
  const DvaeTensors n(m);
  const DvaeNoise v = net->NoiseVariances(x, x, p.hidden, n.scale2());
  CHECK(v.alpha.sizes() == x.sizes());
  CHECK((v.alpha > 0).all().item<bool>());
  CHECK((v.beta > 0).all().item<bool>());
  CHECK(net->Generate(x.select(1, 0), 7, true, gen).sizes() == torch::IntArrayRef({B, 7, F}));
  // Any length works (the recurrences do not fix T).
  CHECK(net->Run(x.slice(1, 0, 4), x.select(1, 0), false, c10::nullopt).mean.size(1) == 3);
}

TEST_CASE("dvae KL formulas are zero for equal distributions and positive otherwise") {
  const torch::Tensor m = torch::tensor({0.3, -1.0}), l = torch::tensor({-0.5, 0.2});
  CHECK(GaussianKl(m, l, m, l).abs().max().item<double>() < 1e-6);
  CHECK((GaussianKl(m, l, m + 0.5, l) > 0).all().item<bool>());
  const torch::Tensor a = torch::tensor({2.0, 5.0}), b = torch::tensor({0.01, 3.0});
  CHECK(InverseGammaKl(torch::tensor({2.0}), torch::tensor({0.5}), 2.0, torch::tensor({0.5}))
            .abs()
            .item<double>() < 1e-6);
  CHECK((InverseGammaKl(a, b, 2.0, torch::tensor({0.02, 0.02})) > 0).all().item<bool>());
  // Against a Monte Carlo estimate: E_q[log q(v) - log p(v)] for q = IG(3, 2), p = IG(2, 1).
  torch::manual_seed(3);
  const torch::Tensor g =
      at::_standard_gamma(torch::full({200000}, 3.0)) / 2.0;  // Gamma(3, rate 2)
  const torch::Tensor v = 1.0 / g;
  auto log_ig = [&](double al, double be) {
    return al * std::log(be) - std::lgamma(al) - (al + 1) * torch::log(v) - be / v;
  };
  const double mc = (log_ig(3, 2) - log_ig(2, 1)).mean().item<double>();
  const double exact =
      InverseGammaKl(torch::tensor({3.0}), torch::tensor({2.0}), 2.0, torch::tensor({1.0}))
          .item<double>();
  CHECK(exact == Approx(mc).margin(0.01));
}

TEST_CASE("dvae objectives: every parameter the stage trains receives a gradient") {
  torch::manual_seed(0);
  const DvaeManifest m = TinyManifest();
  DvaeNet net = BuildDvaeNet(m);
  const DvaeTensors n(m);
  const torch::Tensor x = torch::randn({4, 10, DvaeValues(m)});
  at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(2);
  SECTION("prior training: decoder, prior, encoder and the initial-state predictor") {
    PriorObjective(net, n, x, 1.0, 0.1, gen).loss.backward();
    int missing = 0;
    for (const auto& kv : net->named_parameters()) {
      const bool noise_head = kv.key().rfind("e_b.", 0) == 0;  // only denoising trains it
      const bool has =
          kv.value().grad().defined() && kv.value().grad().abs().sum().item<double>() > 0;
      if (!noise_head && !has) {
        ++missing;
        UNSCOPED_INFO("no gradient: " << kv.key());
      }
    }
    CHECK(missing == 0);
  }
  SECTION("denoising: every encoder-side parameter, through the fixed decoder") {
    for (torch::Tensor& p : net->DecoderParameters()) p.set_requires_grad(false);
    const DenoiseTerms t = DenoiseObjective(net, n, x, 1.0, 0.1, gen);
    CHECK(std::isfinite(t.loss.item<double>()));
    t.loss.backward();
    for (const torch::Tensor& p : net->EncoderParameters()) {
      CHECK(p.grad().defined());
      if (p.grad().defined()) CHECK(p.grad().abs().sum().item<double>() > 0);
    }
  }
}
