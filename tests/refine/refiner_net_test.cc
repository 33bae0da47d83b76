// The temporal refiner network: what a new one computes, any length, its settings checked.
#include "refine/refiner_net.h"

#include <catch2/catch.hpp>

using namespace motionfork;
using Catch::Contains;

namespace {

RefinerOptions Small() { return {8, 32, 8, {1, 2, 4}, 3}; }

}  // namespace

TEST_CASE("a new refiner smooths: constant and straight motion come back, noise is damped") {
  torch::manual_seed(0);
  TemporalRefiner net(Small(), 6, 6);
  torch::NoGradGuard no_grad;
  for (int64_t T : {1, 2, 7, 40}) {
    const torch::Tensor constant = torch::full({2, T, 6}, 0.7);
    CHECK(net->forward(constant).sizes() == torch::IntArrayRef({2, T, 6}));
    CHECK(net->forward(constant).abs().max().item<double>() < 1e-6);
  }
  // A straight line in time: unchanged away from the edges (a symmetric filter keeps lines).
  const torch::Tensor line = torch::linspace(-1, 1, 40).reshape({1, 40, 1}).expand({1, 40, 6});
  const torch::Tensor inner = net->forward(line).slice(1, 3, 37);
  CHECK(inner.abs().max().item<double>() < 1e-5);
  // Alternating noise: the correction takes most of it away.
  const torch::Tensor zigzag =
      (torch::arange(40) % 2 * 2 - 1).to(torch::kFloat32).reshape({1, 40, 1}).expand({1, 40, 6});
  const torch::Tensor out = zigzag + net->forward(zigzag);
  CHECK(out.slice(1, 3, 37).abs().max().item<double>() < 0.5);
}

TEST_CASE("refiner settings are checked, naming the field") {
  RefinerOptions o = Small();
  CHECK(o.reach() == 8);  // 1 + 1 + 2 + 4
  o.dilations = {1, 0};
  CHECK_THROWS_WITH(ValidateRefinerOptions(o, "refiner"), Contains("dilations"));
  o = Small();
  o.stride = 40;
  CHECK_THROWS_WITH(ValidateRefinerOptions(o, "refiner"), Contains("stride"));
  o = Small();
  o.channels = 0;
  CHECK_FALSE(o.enabled());
  CHECK_NOTHROW(ValidateRefinerOptions(o, "refiner"));  // none: nothing else is checked
  o = Small();
  o.linear_reach = -1;
  CHECK_THROWS_WITH(TemporalRefiner(o, 3, 3), Contains("linear_reach"));
}
