// Training, bundles and imputation on a tiny HG-VAE trained in code on synthetic walks.
#include "imputation/hgvae_model.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "bundle/hgvae_bundle.h"
#include "core/error.h"
#include "imputation/hgvae_experiments.h"
#include "imputation/motion_imputation.h"
#include "imputation/occlusion.h"
#include "imputation/tiny_hgvae.h"
#include "io/file_util.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;

namespace {

namespace fs = std::filesystem;

// One tiny model for the whole file (trained once, ~seconds).
const std::string& TinyModelDir() {
  static testing::TempDir dir;
  static const bool done = [] {
    testing::WriteTinyHgvaeBundle(dir.file("m"), 8, 8);
    return true;
  }();
  (void)done;
  static const std::string path = dir.file("m");
  return path;
}

std::vector<double> Column(const std::string& csv, const std::string& name) {
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  int col = -1, i = 0;
  std::stringstream hs(header);
  for (std::string h; std::getline(hs, h, ','); ++i) {
    if (h == name) col = i;
  }
  REQUIRE(col >= 0);
  std::vector<double> out;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::string v;
    for (int k = 0; k <= col; ++k) std::getline(ls, v, ',');
    out.push_back(std::stod(v));
  }
  return out;
}

}  // namespace

TEST_CASE("hgvae training: the loss and the held-out error fall, a bundle and log are written") {
  const std::string dir = TinyModelDir();
  CHECK(fs::exists(dir + "/hgvae.yaml"));
  CHECK(fs::exists(dir + "/hgvae.pt"));
  const std::vector<double> nll = Column(dir + "/log.csv", "nll");
  const std::vector<double> mse = Column(dir + "/log.csv", "held_out_mse_m2");
  REQUIRE(nll.size() == 8);
  CHECK(nll.back() < nll.front());
  CHECK(mse.back() < mse.front());
}

TEST_CASE("hgvae training: a resumed run gives the same weights as an uninterrupted one") {
  testing::TempDir dir;
  const HgvaeTrainConfig cfg = testing::TinyHgvaeConfig(6, 2);
  HgvaeManifest base;
  base.protocol = "bandai";
  base.fps = 30;
  base.skeleton = testing::MakeHumanoid()->ToSpec();
  const HgvaeData data = testing::TinyHgvaeData(8, 40);
  TrainHgvae(cfg, base, data, dir.file("whole"), {});
  const HgvaeTrainSummary first = TrainHgvae(cfg, base, data, dir.file("split"), {}, 1);
  CHECK(first.epochs_done == 1);
  const HgvaeTrainSummary second = TrainHgvae(cfg, base, data, dir.file("split"), {});
  CHECK(second.first_epoch == 1);
  CHECK(ReadFileBytes(dir.file("whole/hgvae.pt")) == ReadFileBytes(dir.file("split/hgvae.pt")));
}

TEST_CASE("hgvae model: load gives the same scores every time, bad bundles are named") {
  const HgvaeModel a = LoadHgvaeModel(TinyModelDir()), b = LoadHgvaeModel(TinyModelDir());
  CHECK(a.window() == 8);
  CHECK(a.coords() == 48);
  const std::vector<float> w = PoseVectorsWithoutRoot(testing::MakeWalkingMotion(8, 30.0, 999));
  CHECK(a.Score(w) == b.Score(w));
  CHECK(a.Score(w).size() == 1);
  testing::TempDir dir;
  fs::create_directories(dir.file("broken"));
  fs::copy_file(TinyModelDir() + "/hgvae.yaml", dir.file("broken/hgvae.yaml"));
  CHECK_THROWS_WITH(LoadHgvaeModel(dir.file("broken")),
                    Contains("hgvae.pt") && Contains("missing"));
  std::ofstream(dir.file("broken/hgvae.pt")) << "not weights";
  CHECK_THROWS_WITH(LoadHgvaeModel(dir.file("broken")), Contains("hgvae.pt"));
  CHECK_THROWS_AS(a.Score(std::vector<float>(47)), std::invalid_argument);
  CHECK_THROWS_WITH(a.ClassIndex("walk"), Contains("unconditional"));
}

TEST_CASE(
    "hgvae imputation: observed values kept, missing ones closer than the mean, best step kept") {
  const HgvaeModel model = LoadHgvaeModel(TinyModelDir());
  std::vector<float> windows;
  for (int s = 0; s < 16; ++s) {
    const std::vector<float> p =
        PoseVectorsWithoutRoot(testing::MakeWalkingMotion(8, 30.0, 500 + s));
    windows.insert(windows.end(), p.begin(), p.end());
  }
  const std::vector<uint8_t> mask = RandomOcclusion(16, 8 * 48, 0.3, 1);
  std::vector<float> degraded = windows;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (mask[i]) degraded[i] = std::numeric_limits<float>::quiet_NaN();
  }
  ImputeOptions o;
  o.steps = 20;
  o.learning_rate = 0.1;
  const ImputeResult r = model.Impute(degraded, mask, o);
  const std::vector<float> mean = model.MeanImpute(degraded, mask);
  double se_model = 0, se_mean = 0;
  for (size_t i = 0; i < mask.size(); ++i) {
    REQUIRE(std::isfinite(r.windows[i]));
    if (!mask[i]) {
      CHECK(r.windows[i] == windows[i]);
      continue;
    }
    se_model += std::pow(r.windows[i] - windows[i], 2);
    se_mean += std::pow(mean[i] - windows[i], 2);
  }
  INFO("MSE model " << se_model << " mean " << se_mean);
  CHECK(se_model < 0.7 * se_mean);
  // The objective is the bundle's OoD score (joint): each window keeps its best step, never below
  // the mean start.
  REQUIRE(model.manifest().ood_score == o.objective);
  for (size_t w = 0; w < r.best_step.size(); ++w) CHECK(r.score_after[w] >= r.score_before[w]);
  // No steps: the mean start is kept.
  o.steps = 0;
  const ImputeResult none = model.Impute(degraded, mask, o);
  CHECK(none.windows == std::vector<float>(mean.begin(), mean.end()));
}

TEST_CASE("hgvae model: several threads give the same imputations, scores and figures as one") {
  HgvaeModel model = LoadHgvaeModel(TinyModelDir());
  const int count = 150;  // three chunks, the last one short
  std::vector<float> windows;
  for (int s = 0; s < count; ++s) {
    const std::vector<float> p =
        PoseVectorsWithoutRoot(testing::MakeWalkingMotion(8, 30.0, 700 + s));
    windows.insert(windows.end(), p.begin(), p.end());
  }
  const std::vector<uint8_t> mask = RandomOcclusion(count, 8 * 48, 0.2, 3);
  ImputeOptions o;
  o.steps = 5;
  const ImputeResult one = model.Impute(windows, mask, o);
  const std::vector<double> score_one = model.Score(windows);
  const HgvaeWindowFigures fig_one = model.Evaluate(windows, 9);
  model.set_threads(3);
  const ImputeResult three = model.Impute(windows, mask, o);
  CHECK(three.windows == one.windows);
  CHECK(three.score_before == one.score_before);
  CHECK(three.score_after == one.score_after);
  CHECK(three.best_step == one.best_step);
  CHECK(model.Score(windows) == score_one);
  REQUIRE(score_one.size() == static_cast<size_t>(count));
  const HgvaeWindowFigures fig_three = model.Evaluate(windows, 9);
  CHECK(fig_three.elbo == fig_one.elbo);
  CHECK(fig_three.recon_mse_sampled == fig_one.recon_mse_sampled);
  CHECK(fig_three.kl_levels == fig_one.kl_levels);
  CHECK(fig_three.joint_score == fig_one.joint_score);
  // Chunks draw their own latents: another seed, other samples.
  CHECK(model.Evaluate(windows, 10).elbo != fig_one.elbo);
  CHECK_THROWS_WITH(model.set_threads(0), Contains(">= 1 thread"));
}

TEST_CASE("hgvae imputation: an all-missing window and a mask of the wrong size are refused") {
  const HgvaeModel model = LoadHgvaeModel(TinyModelDir());
  const std::vector<float> w = PoseVectorsWithoutRoot(testing::MakeWalkingMotion(8));
  CHECK_THROWS_WITH(model.Impute(w, std::vector<uint8_t>(w.size(), 1), {}),
                    Contains("every value missing"));
  CHECK_THROWS_WITH(model.Impute(w, std::vector<uint8_t>(w.size() - 1, 0), {}), Contains("mask"));
}

TEST_CASE("motion imputation: a long motion is covered, the root must be known") {
  const HgvaeModel model = LoadHgvaeModel(TinyModelDir());
  const Motion m = testing::MakeWalkingMotion(21);
  std::vector<uint8_t> missing = MaskFromSpec("joints:Hand_L,LowerArm_L", model.skeleton(), 21, 0);
  const MotionImputation r = ImputeMotion(model, m, missing, ImputeOptions{});
  CHECK(r.missing_values == 21 * 2 * 3);
  CHECK(r.window_starts == std::vector<int>{0, 8, 13});
  for (size_t i = 0; i < missing.size(); ++i) {
    if (!missing[i]) CHECK(r.motion.positions()[i] == Approx(m.positions()[i]).margin(1e-6));
  }
  CHECK(CoveringWindowStarts(16, 8, 8) == std::vector<int>{0, 8});
  missing[3 * 17 * 5 + 1] = 1;  // frame 5, root y
  CHECK_THROWS_WITH(ImputeMotion(model, m, missing, ImputeOptions{}),
                    Contains("frame 5") && Contains("root"));
  CHECK_THROWS_WITH(ImputeMotion(model, testing::MakeWalkingMotion(5), std::vector<uint8_t>(5 * 51),
                                 ImputeOptions{}),
                    Contains("8 frames"));
  const std::vector<WindowScore> s = ScoreMotion(model, m, 4);
  CHECK(s.size() == 5);  // 0, 4, 8, 12, 13
  CHECK(s.back().start == 13);
}

TEST_CASE("hgvae ood: scores separate impossible bodies from walks") {
  const HgvaeModel model = LoadHgvaeModel(TinyModelDir());
  std::vector<float> windows;
  for (int s = 0; s < 24; ++s) {
    const std::vector<float> p =
        PoseVectorsWithoutRoot(testing::MakeWalkingMotion(8, 30.0, 700 + s));
    windows.insert(windows.end(), p.begin(), p.end());
  }
  const std::vector<double> clean = model.Score(windows);
  const std::vector<double> stretched = model.Score(ScaleBones(model.skeleton(), windows, 2.0f));
  CHECK(Auroc(clean, stretched) > 0.9);
}

TEST_CASE("hgvae sampling: shapes, seeds") {
  const HgvaeModel model = LoadHgvaeModel(TinyModelDir());
  const std::vector<float> a = model.Sample(3, -1, 4), b = model.Sample(3, -1, 4),
                           c = model.Sample(3, -1, 5);
  CHECK(a.size() == 3u * 8 * 48);
  CHECK(a == b);
  CHECK(a != c);
  CHECK_THROWS_AS(model.Sample(0, -1, 0), std::invalid_argument);
}
