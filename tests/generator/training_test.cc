// Training, bundles and the Forecaster on synthetic data built in code.
#include "generator/training/training.h"

#include <filesystem>

#include "bodyparts/part_plan.h"
#include "bundle/generator_bundle.h"
#include "core/joint_selection.h"
#include "generator/inference/forecaster.h"
#include "synthetic_training.h"
#include "test_support.h"
#include "torch_catch.h"
#include "torch_util/threads.h"

using namespace motionfork;
using testing::ModelFor;
using testing::SyntheticDataset;
using testing::TinyConfig;

TEST_CASE("training on synthetic motion lowers every loss term, resumes, and saves a bundle") {
  testing::TempDir out, cache;
  const Dataset ds = SyntheticDataset(8, 60);
  const GeneratorTrainConfig cfg = TinyConfig();
  const ModelConfig model = ModelFor(ds, cfg);
  const TrainingWindows data = BuildTrainingWindows(ds, cfg.training.window_stride, cfg.multimodal,
                                                    "", cache.path().string());
  REQUIRE(data.windows.size() == 6u * 23);  // 6 train clips of 60 frames, starts 0, 2, ..., 44
  size_t with_mm = 0;
  for (const auto& m : data.multimodal) with_mm += !m.empty();
  CHECK(with_mm > 0);
  std::vector<std::vector<std::pair<std::string, double>>> epochs;
  TrainCallbacks cb;
  cb.epoch = [&](int, const std::vector<std::pair<std::string, double>>& terms, double) {
    epochs.push_back(terms);
  };
  TrainSummary first =
      TrainGenerator(cfg, model, data, out.path().string(), {}, cb, /*stop_after=*/4);
  CHECK(first.epochs_done == 4);
  TrainSummary second = TrainGenerator(cfg, model, data, out.path().string(), {}, cb);
  CHECK(second.first_epoch == 4);
  CHECK(second.epochs_done == 8);
  REQUIRE(epochs.size() == 8);
  for (size_t k = 0; k < epochs[0].size(); ++k) {
    const std::string& name = epochs[0][k].first;
    INFO(name << ": first epoch " << epochs.front()[k].second << ", last "
              << epochs.back()[k].second);
    if (name.rfind("diversity", 0) == 0) continue;  // diversity is traded against accuracy
    CHECK(epochs.back()[k].second < epochs.front()[k].second);
  }
  CHECK(std::filesystem::exists(out.path() / "log.csv"));

  // Bundle -> Forecaster: shapes, determinism, control, errors.
  const Forecaster f = LoadForecaster(out.path().string());
  const Motion history = ds.clips[3].motion;  // a test clip
  ForecastRequest req;
  req.k = 6;
  req.seed = 11;
  const Forecast a = f.Predict(history, 0, req), b = f.Predict(history, 0, req);
  CHECK(a.futures.size() == 6u * 10 * 17 * 3);
  CHECK(a.futures == b.futures);
  req.seed = 12;
  CHECK(f.Predict(history, 0, req).futures != a.futures);
  for (const std::string part : {"legs", "upper"}) {
    req.fixed_parts = {part};
    const Forecast c = f.Predict(history, 0, req);
    const PartPlan& plan = f.parts();
    const int p = plan.Index(part);
    float fixed_spread = 0, other_spread = 0;
    for (int k = 1; k < c.k; ++k) {
      for (int t = 0; t < c.t_pred; ++t) {
        for (int j = 1; j < 17; ++j) {
          const bool in_part =
              std::find(plan.nodes[p].begin(), plan.nodes[p].end(), j - 1) != plan.nodes[p].end();
          for (int ax = 0; ax < 3; ++ax) {
            const size_t i0 = ((static_cast<size_t>(0) * c.t_pred + t) * 17 + j) * 3 + ax;
            const size_t ik = ((static_cast<size_t>(k) * c.t_pred + t) * 17 + j) * 3 + ax;
            const float d = std::abs(c.futures[ik] - c.futures[i0]);
            (in_part ? fixed_spread : other_spread) =
                std::max(in_part ? fixed_spread : other_spread, d);
          }
        }
      }
    }
    INFO("fixed part " << part);
    if (p == 0) CHECK(fixed_spread == 0.0f);  // the first part sees only the history
    CHECK(other_spread > 0.0f);
  }
  req.fixed_parts = {"tail"};
  CHECK_THROWS_WITH(f.Predict(history, 0, req), Catch::Contains("no body part 'tail'"));
  req.fixed_parts = {};
  CHECK_THROWS_WITH(f.Predict(history, 58, req), Catch::Contains("needs 5 history frames"));
  std::vector<float> bad = history.positions();
  CHECK_THROWS_WITH(f.PredictRootRelative(std::vector<float>(5 * 16 * 3, NAN), 1, req),
                    Catch::Contains("NaN"));
}

TEST_CASE("a fixed later part keeps its own joints when earlier parts are the same") {
  // With every part fixed, all K futures are identical.
  testing::TempDir out, cache;
  const Dataset ds = SyntheticDataset(4, 40);
  GeneratorTrainConfig cfg = TinyConfig();
  cfg.training.epochs = 1;
  cfg.training.lr_constant_epochs = 1;
  const TrainingWindows data = BuildTrainingWindows(ds, 3, cfg.multimodal, "", "");
  TrainGenerator(cfg, ModelFor(ds, cfg), data, out.path().string(), {}, {});
  const Forecaster f = LoadForecaster(out.path().string());
  ForecastRequest req;
  req.k = 4;
  req.fixed_parts = {"legs", "upper"};
  const Forecast c = f.Predict(ds.clips[0].motion, 0, req);
  const size_t one = c.futures.size() / 4;
  for (int k = 1; k < 4; ++k) {
    CHECK(std::equal(c.futures.begin(), c.futures.begin() + one, c.futures.begin() + k * one));
  }
}

TEST_CASE("bundles with missing or foreign files get clear errors") {
  testing::TempDir out;
  CHECK_THROWS_WITH(LoadForecaster((out.path() / "nope").string()), Catch::Contains("not found"));
  std::filesystem::create_directories(out.path() / "b");
  CHECK_THROWS_WITH(LoadForecaster((out.path() / "b").string()), Catch::Contains("model.yaml"));
}
