// Issue 30's accuracy checks for the bf16 products, on every fifth window of the Bandai test split
// with the shipped model: the futures of --precision bf16 against fp32's for the same seed (each
// future's mean joint distance over its frames: every future within 1 mm, with the repair and
// without), and the protocol figures within 0.001 m. Skipped, visibly, on CPUs without AVX512-BF16
// (MOTIONFORK_REQUIRE_BF16=1 makes that a failure) and without
// ../shared/data/bandai.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <string>

#include "bandai_real_data.h"
#include "bundle/generator_bundle.h"
#include "eval/evaluate.h"
#include "eval/test_set.h"
#include "generator/kernels/precision.h"
#include "generator/training/generator_predictor.h"
#include "test_support.h"

using namespace motionfork;

namespace {

// Every `stride`-th window of the test set (its multimodal sets rebuilt over those windows).
TestSet EveryNth(const TestSet& all, int stride) {
  TestSet out = all;
  out.windows.clear();
  out.action.clear();
  out.histories.clear();
  out.futures.clear();
  out.root_futures.clear();
  const size_t h = static_cast<size_t>(all.t_his) * all.num_joints() * 3,
               f = static_cast<size_t>(all.t_pred) * all.pose_dims;
  for (int i = 0; i < all.num_windows(); i += stride) {
    out.windows.push_back(all.windows[i]);
    out.action.push_back(all.action[i]);
    out.histories.insert(out.histories.end(), all.history(i), all.history(i) + h);
    out.futures.insert(out.futures.end(), all.future(i), all.future(i) + f);
    out.root_futures.insert(out.root_futures.end(), all.root_future(i),
                            all.root_future(i) + static_cast<size_t>(all.t_pred) * 3);
  }
  return out;
}

}  // namespace

TEST_CASE("bf16 products: futures within 1 mm of fp32's and eval figures within 0.001 m") {
  if (!Bf16ProductsAvailable()) {
    const char* require = std::getenv("MOTIONFORK_REQUIRE_BF16");
    REQUIRE_FALSE((require && std::string(require) == "1"));
    WARN("SKIPPED: this CPU has no AVX512-BF16 (the bf16 products do not run here)");
    return;
  }
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  testing::TempDir cache;
  const testing::RealBandai bandai = testing::LoadRealBandai(data, cache.path().string());
  const ProtocolOptions& p = bandai.protocol;
  const Dataset& ds = bandai.dataset;
  std::vector<const Clip*> test;
  for (const Clip& c : ds.clips)
    if (c.split == Split::kTest) test.push_back(&c);
  TestSet ts = EveryNth(BuildTestSet(test, p), 5);
  REQUIRE(ts.num_windows() > 500);
  AttachMultimodalSets(&ts, p.multimodal_threshold, "", p.name);

  const std::string model = std::string(MOTIONFORK_SOURCE_DIR) + "/models/bandai";
  auto predictor = [&](Precision precision, bool repair) {
    Forecaster f = LoadForecaster(model);
    f.SetPrecision(precision);
    REQUIRE(f.precision() == precision);
    return GeneratorPredictor(std::move(f), "bandai", "", repair);
  };

  for (bool repair : {false, true}) {
    GeneratorPredictor fp32 = predictor(Precision::kFp32, repair),
                       bf16 = predictor(Precision::kBf16, repair);
    // Futures of the same seed: each future's mean joint distance (mm) over its frames.
    const int J = ts.num_joints(), K = 50;
    double worst_future = 0, sum = 0, worst_joint = 0;
    int64_t futures = 0;
    std::vector<float> a, b;
    for (int w = 0; w < ts.num_windows(); ++w) {
      const std::vector<float> history(ts.history(w),
                                       ts.history(w) + static_cast<size_t>(ts.t_his) * J * 3);
      const PredictRequest request{K, static_cast<uint64_t>(w), -1};
      fp32.Predict(history, request, &a);
      bf16.Predict(history, request, &b);
      const size_t per_future = static_cast<size_t>(ts.t_pred) * J;
      for (int k = 0; k < K; ++k) {
        double future = 0;
        for (size_t j = 0; j < per_future; ++j) {
          const size_t i = (k * per_future + j) * 3;
          const double d =
              1e3 * std::sqrt(std::pow(a[i] - b[i], 2) + std::pow(a[i + 1] - b[i + 1], 2) +
                              std::pow(a[i + 2] - b[i + 2], 2));
          future += d;
          worst_joint = std::max(worst_joint, d);
        }
        future /= static_cast<double>(per_future);
        worst_future = std::max(worst_future, future);
        sum += future;
        ++futures;
      }
    }
    WARN("bf16 against fp32, repair " << (repair ? "on" : "off") << ", " << ts.num_windows()
                                      << " test windows x " << K << " futures: mean "
                                      << sum / futures << " mm, worst future " << worst_future
                                      << " mm, worst joint " << worst_joint << " mm");
    // Measured on 2026-12-05 (AMD EPYC): worst future 0.61 mm raw, 0.89 mm repaired (the repair
    // moves a pose that crosses a range's edge in one precision and not the other by whole Adam
    // steps: the worst joint moved 39 mm); with every hidden layer in bf16 it was 1.19 / 1.46 mm.
    CHECK(worst_future <= 1.0);

    // The protocol figures of the same windows.
    EvalOptions o;
    o.threads = 2;
    const Figures x = Evaluate(fp32, ts, o).overall, y = Evaluate(bf16, ts, o).overall;
    WARN("eval, repair " << (repair ? "on" : "off") << ": ADE " << x.ade << " / " << y.ade
                         << ", FDE " << x.fde << " / " << y.fde << ", APD " << x.apd << " / "
                         << y.apd << ", MMADE " << x.mmade << " / " << y.mmade << ", MMFDE "
                         << x.mmfde << " / " << y.mmfde);
    for (auto [u, v] : {std::pair{x.ade, y.ade},
                        {x.fde, y.fde},
                        {x.apd, y.apd},
                        {x.mmade, y.mmade},
                        {x.mmfde, y.mmfde}}) {
      CHECK(std::abs(u - v) <= 0.001);
    }
  }
}
