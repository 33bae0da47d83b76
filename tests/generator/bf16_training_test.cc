// Training with bf16 products (issue 30): the differentiable product (model/bf16_matmul.h) and a
// generator trained with it (training.precision).
#include <cstdlib>
#include <map>
#include <tuple>
#include <vector>

#include "bf16_skip.h"
#include "generator/kernels/backend.h"
#include "generator/kernels/bf16_product.h"
#include "generator/kernels/cpu_features.h"
#include "generator/kernels/precision.h"
#include "generator/model/bf16_matmul.h"
#include "generator/training/training.h"
#include "synthetic_training.h"
#include "test_support.h"
#include "torch_catch.h"

using namespace motionfork;

namespace {

bool Bf16OrSkip() { return testing::Bf16OrSkip("training in bf16 is refused here"); }

torch::Tensor Rounded(const torch::Tensor& t) { return t.to(torch::kBFloat16).to(torch::kDouble); }

// The product and both gradients against the exact sums (double) of the bf16-rounded inputs,
// within float32 summation (relative 1e-5 of the sum of |terms|), for shapes that do and do not
// fill the kernel's row blocks and padded columns.
void CheckProductAndGradients() {
  torch::manual_seed(3);
  for (const auto& [m, k, n] : std::vector<std::tuple<int64_t, int64_t, int64_t>>{
           {1, 1, 1}, {70, 33, 20}, {130, 64, 48}, {257, 32, 32}}) {
    INFO("x [" << m << ", " << k << "] w [" << k << ", " << n << "]");
    const torch::Tensor x = torch::randn({m, k}).requires_grad_(true);
    const torch::Tensor w = torch::randn({k, n}).requires_grad_(true);
    const torch::Tensor dy = torch::randn({m, n});
    const torch::Tensor y = Bf16MatMul(x, w);
    y.backward(dy);
    auto check = [](const torch::Tensor& got, const torch::Tensor& a, const torch::Tensor& b) {
      const torch::Tensor want = Rounded(a).mm(Rounded(b));
      const torch::Tensor scale = Rounded(a).abs().mm(Rounded(b).abs());
      CHECK(got.scalar_type() == torch::kFloat);
      CHECK(((got.to(torch::kDouble) - want).abs() - 1e-5 * scale - 1e-30).max().item<double>() <=
            0);
    };
    check(y.detach(), x.detach(), w.detach());
    check(x.grad(), dy, w.detach().t());
    check(w.grad(), x.detach().t(), dy);
    // Not the float32 product: the inputs were rounded (the check above would pass for either
    // only if rounding changed nothing).
    CHECK((y.detach() - x.detach().mm(w.detach())).abs().max().item<float>() > 0);
  }
}

}  // namespace

TEST_CASE("bf16 training product: portable kernel, product and both gradients") {
  kernels::UsePortableKernels(true);
  CheckProductAndGradients();
  kernels::UsePortableKernels(false);
}

TEST_CASE("bf16 training product: AVX512-BF16 kernel, product and both gradients") {
  if (!Bf16OrSkip()) return;
  CheckProductAndGradients();
}

TEST_CASE("training with bf16 products lowers the losses as float32 training does") {
  const Dataset ds = testing::SyntheticDataset(8, 60);
  GeneratorTrainConfig cfg = testing::TinyConfig();
  if (!Bf16OrSkip()) {
    cfg.training.precision = Precision::kBf16;
    testing::TempDir out, cache;
    const TrainingWindows data = BuildTrainingWindows(ds, cfg.training.window_stride,
                                                      cfg.multimodal, "", cache.path().string());
    CHECK_THROWS_WITH(
        TrainGenerator(cfg, testing::ModelFor(ds, cfg), data, out.path().string(), {}, {}),
        Catch::Contains("AVX512-BF16"));
    return;
  }
  cfg.generator.hidden = 64;  // the residual block's product: [rows, 64] x [64, 64]
  const ModelConfig model = testing::ModelFor(ds, cfg);
  testing::TempDir cache;
  const TrainingWindows data = BuildTrainingWindows(ds, cfg.training.window_stride, cfg.multimodal,
                                                    "", cache.path().string());
  std::map<std::string, std::vector<std::vector<std::pair<std::string, double>>>> runs;
  for (const Precision p : {Precision::kFp32, Precision::kBf16}) {
    cfg.training.precision = p;
    testing::TempDir out;
    TrainCallbacks cb;
    auto& epochs = runs[PrecisionName(p)];
    cb.epoch = [&](int, const std::vector<std::pair<std::string, double>>& terms, double) {
      epochs.push_back(terms);
    };
    TrainGenerator(cfg, model, data, out.path().string(), {}, cb);
    REQUIRE(epochs.size() == static_cast<size_t>(cfg.training.epochs));
  }
  const auto &fp32 = runs["fp32"], &bf16 = runs["bf16"];
  for (size_t k = 0; k < fp32[0].size(); ++k) {
    const std::string& name = fp32[0][k].first;
    INFO(name << ": fp32 " << fp32.front()[k].second << " -> " << fp32.back()[k].second << ", bf16 "
              << bf16.front()[k].second << " -> " << bf16.back()[k].second);
    // The first epoch's steps start from the same weights: within bf16's rounding.
    CHECK(bf16.front()[k].second == Approx(fp32.front()[k].second).epsilon(0.02).margin(1e-4));
    if (name.rfind("diversity", 0) == 0) continue;  // traded against accuracy
    CHECK(bf16.back()[k].second < bf16.front()[k].second);
    // And end where float32's run ends, within the spread of runs that differ by rounding alone.
    CHECK(bf16.back()[k].second / fp32.back()[k].second == Approx(1).margin(0.5));
  }
}
