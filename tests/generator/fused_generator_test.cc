#include "generator/inference/fused_generator.h"

#include <cmath>

#include "generator/kernels/backend.h"
#include "generator/kernels/cpu_features.h"
#include "generator/kernels/panel_product.h"
#include "generator/kernels/tanh.h"
#include "generator/model/generator_net.h"
#include "test_support.h"
#include "torch_catch.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

// Each test runs on both backends of the kernels (generator/kernels/backend.h), as two test
// cases: the portable one on every CPU, the AVX-512 one where it runs.
struct PortableKernels {
  PortableKernels() { kernels::UsePortableKernels(true); }
  ~PortableKernels() { kernels::UsePortableKernels(false); }
};

// The AVX-512 backend's cases skip (print "SKIPPED: ...", which CTest shows as a skip) in a build
// without that backend (MOTIONFORK_AVX512=OFF, or a compiler or target without AVX-512) and on a
// CPU without AVX-512, which cannot run those kernels at all (the machines CI runs on change from
// AVX-512 Xeons and EPYCs to EPYCs without it). MOTIONFORK_REQUIRE_AVX512=1 makes the latter a
// failure, for a machine known to have AVX-512.
bool Avx512OrSkip() {
  if (!kernels::Avx512Built()) {
    WARN(
        "SKIPPED: this build has no AVX-512 kernels (MOTIONFORK_AVX512=OFF or no compiler "
        "support); the portable ones are tested");
    return false;
  }
  if (!kernels::Cpu().avx512) {
    if (const char* need = std::getenv("MOTIONFORK_REQUIRE_AVX512"); need && *need == '1')
      FAIL("MOTIONFORK_REQUIRE_AVX512=1 but this CPU has no AVX-512");
    WARN("SKIPPED: this CPU has no AVX-512; the portable kernels are tested");
    return false;
  }
  REQUIRE(kernels::ActiveBackend() == kernels::Backend::kAvx512);
  return true;
}

// Batch-norm statistics away from their initial 0 / 1, so folding them is exercised.
void RandomiseNorms(GeneratorNetImpl& net) {
  torch::NoGradGuard no_grad;
  for (auto& b : net.named_buffers()) {
    if (b.key().find("running_var") != std::string::npos) b.value().uniform_(0.5, 2.0);
    if (b.key().find("running_mean") != std::string::npos) b.value().uniform_(-0.3, 0.3);
  }
  for (auto& p : net.named_parameters()) {
    if (p.key().find("gamma") != std::string::npos) p.value().uniform_(0.5, 1.5);
    if (p.key().find("beta") != std::string::npos) p.value().uniform_(-0.2, 0.2);
  }
}

// Max |fused - LibTorch| over the futures of `histories` x k samples.
double MaxDifference(const GeneratorOptions& o, const std::vector<std::vector<int64_t>>& parts,
                     int64_t histories, int64_t k, const std::vector<bool>& fixed, uint64_t seed) {
  torch::manual_seed(seed);
  GeneratorNet net(o, parts);
  RandomiseNorms(*net);
  net->eval();
  torch::NoGradGuard no_grad;
  const torch::Tensor h = torch::randn({histories, o.t_his, o.num_nodes, 3}) * 0.3;
  std::vector<torch::Tensor> z;
  std::vector<const float*> zp;
  for (size_t p = 0; p < parts.size(); ++p) {
    torch::Tensor zi = torch::randn({histories * k, o.nz});
    if (p < fixed.size() && fixed[p]) {
      zi = zi.view({histories, k, o.nz})
               .select(1, 0)
               .unsqueeze(1)
               .expand({histories, k, o.nz})
               .reshape({histories * k, o.nz})
               .contiguous();
    }
    z.push_back(zi);
    zp.push_back(z.back().data_ptr<float>());
  }
  const torch::Tensor want = net->forward(h, z, fixed).slice(1, o.t_his).contiguous();
  FusedGenerator fast(*net);
  torch::Tensor got = torch::empty_like(want);
  fast.Predict(h.data_ptr<float>(), histories, k, zp, fixed, got.data_ptr<float>());
  return (got - want).abs().max().item<double>();
}

GeneratorOptions Sizes(int nodes, int hidden, int n_pre, bool batch_norm) {
  GeneratorOptions o;
  o.num_nodes = nodes;
  o.t_his = 7;
  o.t_pred = 13;
  o.n_pre = n_pre;
  o.hidden = hidden;
  o.blocks = 2;
  o.nz = 5;
  o.batch_norm = batch_norm;
  return o;
}

void TanhAccuracy() {
  std::vector<float> x;
  for (int i = -200000; i <= 200000; ++i) x.push_back(static_cast<float>(i) * 1e-4f);
  for (float v : {-1e4f, -30.0f, -9.5f, 9.5f, 30.0f, 1e4f, 1e-30f, -1e-30f, 0.0f}) x.push_back(v);
  std::vector<float> y = x;
  kernels::Tanh(y.data(), static_cast<int64_t>(y.size()));
  double worst = 0;
  for (size_t i = 0; i < x.size(); ++i)
    worst = std::max(worst, std::abs(double(y[i]) - std::tanh(double(x[i]))));
  CHECK(worst < 3e-7);
  float nan = std::nanf("");
  kernels::Tanh(&nan, 1);
  CHECK(std::isnan(nan));
}

void MatMulShapes() {
  for (int64_t m : {1, 5, 12, 13, 40, 96, 103}) {
    for (int64_t kk : {1, 7, 30}) {
      for (int64_t cols : {1, 16, 30, 33, 64}) {
        std::vector<float> x(m * kk), w(kk * cols);
        for (size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.37 * i);
        for (size_t i = 0; i < w.size(); ++i) w[i] = std::cos(0.11 * i);
        const kernels::PackedWeight pw = kernels::PackWeight(w.data(), kk, cols);
        kernels::AlignedFloats z(m * pw.padded);
        kernels::MatMul(x.data(), m, kk, pw, z.get());
        double worst = 0;
        for (int64_t r = 0; r < m; ++r)
          for (int64_t c = 0; c < cols; ++c) {
            double want = 0;
            for (int64_t i = 0; i < kk; ++i) want += double(x[r * kk + i]) * w[i * cols + c];
            worst = std::max(worst, std::abs(want - z.get()[r * pw.padded + c]));
          }
        INFO("m " << m << " k " << kk << " cols " << cols);
        CHECK(worst < 1e-4);
      }
    }
  }
}

void SameFutures() {
  PinThreads(1);
  // H36M-like: 16 nodes, two parts; odd sizes: 20 nodes (tiles of 12 cross samples), hidden 48
  // and 96 (column tails), no batch norm, three parts.
  const std::vector<std::vector<int64_t>> two16 = {{0, 1, 2, 3, 4, 5},
                                                   {6, 7, 8, 9, 10, 11, 12, 13, 14, 15}};
  std::vector<std::vector<int64_t>> three20 = {
      {0, 1, 2, 3, 4, 5, 6}, {7, 8, 9, 10, 11, 12}, {13, 14, 15, 16, 17, 18, 19}};
  CHECK(MaxDifference(Sizes(16, 64, 10, true), two16, 2, 6, {}, 1) < 1e-5);
  CHECK(MaxDifference(Sizes(20, 48, 8, true), three20, 3, 5, {}, 2) < 1e-5);
  CHECK(MaxDifference(Sizes(20, 96, 8, false), three20, 1, 1, {}, 3) < 1e-5);
  CHECK(MaxDifference(Sizes(16, 256, 10, true), two16, 1, 4, {}, 4) < 1e-5);
  SECTION("with a fixed part, first or later") {
    CHECK(MaxDifference(Sizes(16, 64, 10, true), two16, 2, 6, {true, false}, 5) < 1e-5);
    CHECK(MaxDifference(Sizes(20, 48, 8, true), three20, 2, 5, {false, true, false}, 6) < 1e-5);
    CHECK(MaxDifference(Sizes(20, 48, 8, true), three20, 2, 5, {false, false, true}, 7) < 1e-5);
  }
}

void BatchIndependence() {
  // Small sizes, and H36M's hidden width with 2 and 50 samples (few rows take the products' tail
  // tiles; 50 samples cross the 48-row product chunks).
  struct Case {
    GeneratorOptions o;
    int64_t k;
  };
  GeneratorOptions wide = Sizes(16, 256, 10, true);
  wide.nz = 64;
  for (const Case& c : {Case{Sizes(20, 48, 8, true), 4}, Case{wide, 2}, Case{wide, 50}}) {
    const GeneratorOptions& o = c.o;
    const int64_t k = c.k, half = o.num_nodes / 2;
    std::vector<int64_t> first(half), second(o.num_nodes - half);
    for (int64_t n = 0; n < o.num_nodes; ++n) (n < half ? first[n] : second[n - half]) = n;
    torch::manual_seed(8);
    GeneratorNet net(o, std::vector<std::vector<int64_t>>{first, second});
    RandomiseNorms(*net);
    net->eval();
    const FusedGenerator fast(*net);
    const torch::Tensor h = torch::randn({3, o.t_his, o.num_nodes, 3});
    const torch::Tensor z0 = torch::randn({3 * k, o.nz}), z1 = torch::randn({3 * k, o.nz});
    const int64_t per_sample = int64_t(o.t_pred) * o.num_nodes * 3;
    std::vector<float> all(3 * k * per_sample), one(k * per_sample);
    fast.Predict(h.data_ptr<float>(), 3, k, {z0.data_ptr<float>(), z1.data_ptr<float>()}, {},
                 all.data());
    // History 2 alone gives bit-identical futures.
    const torch::Tensor h2 = h.slice(0, 2).contiguous();
    const torch::Tensor z02 = z0.slice(0, 2 * k).contiguous(),
                        z12 = z1.slice(0, 2 * k).contiguous();
    fast.Predict(h2.data_ptr<float>(), 1, k, {z02.data_ptr<float>(), z12.data_ptr<float>()}, {},
                 one.data());
    INFO("hidden " << o.hidden << ", k " << k);
    CHECK(std::equal(one.begin(), one.end(), all.begin() + 2 * k * per_sample));
    // A wrong number of latents is refused.
    CHECK_THROWS_WITH(
        fast.Predict(h.data_ptr<float>(), 3, k, {z0.data_ptr<float>()}, {}, all.data()),
        Catch::Contains("expected 2 latents"));
  }
}

}  // namespace

TEST_CASE("fused tanh kernel stays within 3e-7 of std::tanh, portable kernels") {
  PortableKernels portable;
  TanhAccuracy();
}

TEST_CASE("fused tanh kernel stays within 3e-7 of std::tanh, AVX-512 kernels") {
  if (Avx512OrSkip()) TanhAccuracy();
}

TEST_CASE(
    "fused matrix product matches a plain one for every tile and padding shape, portable kernels") {
  PortableKernels portable;
  MatMulShapes();
}

TEST_CASE(
    "fused matrix product matches a plain one for every tile and padding shape, AVX-512 kernels") {
  if (Avx512OrSkip()) MatMulShapes();
}

TEST_CASE("fused generator gives the LibTorch network's futures, portable kernels") {
  PortableKernels portable;
  SameFutures();
}

TEST_CASE("fused generator gives the LibTorch network's futures, AVX-512 kernels") {
  if (Avx512OrSkip()) SameFutures();
}

TEST_CASE("fused generator: a sample's future does not depend on its batch, portable kernels") {
  PortableKernels portable;
  BatchIndependence();
}

TEST_CASE("fused generator: a sample's future does not depend on its batch, AVX-512 kernels") {
  if (Avx512OrSkip()) BatchIndependence();
}
