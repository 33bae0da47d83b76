// The public API's pipeline beyond Predict: the history with the futures, prediction files and BVH
// written as the command writes them, the prior's NLL, and history repair (Imputer, Denoiser) on
// tiny models trained in code.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "config/config_paths.h"
#include "config/skeleton_config.h"
#include "core/demo_motion.h"
#include "denoise/tiny_dvae.h"
#include "imputation/tiny_hgvae.h"
#include "io/motion_file.h"
#include "io/prediction_file.h"
#include "motionfork/motionfork.h"
#include "test_support.h"
#include "tiny_bundle.h"
#include "validity/pose_validator.h"

using namespace motionfork;
using Catch::Contains;

namespace {

struct Tiny {
  testing::TempDir dir;
  std::string bundle = dir.file("bundle");
  Tiny() { testing::WriteTinyBundle(bundle, MOTIONFORK_CONFIG_DIR); }
  Model Load() const {
    LoadOptions o;
    o.config_dir = MOTIONFORK_CONFIG_DIR;
    return Model::Load(bundle, o);
  }
};

const std::vector<float>& History() {
  static const std::vector<float> h = testing::TinyBundleHistory(12).positions();
  return h;
}

}  // namespace

TEST_CASE("API version: the library and its headers agree") {
  CHECK(std::string(Version()) == MOTIONFORK_VERSION_STRING);
  CHECK(MOTIONFORK_VERSION_NUMBER == MOTIONFORK_VERSION_MAJOR * 10000 +
                                         MOTIONFORK_VERSION_MINOR * 100 + MOTIONFORK_VERSION_PATCH);
}

TEST_CASE("Futures carry the history they continue, Sequence joins them as the file does") {
  const Tiny tiny;
  const Model model = tiny.Load();
  const Futures f = model.Predict(History(), {3, 5, {}});
  const size_t frame = 17 * 3;
  CHECK(f.history_frames == model.history_frames());
  REQUIRE(f.history.size() == f.history_frames * frame);
  // The last history_frames() frames of the input (the tiny bundle has no constraints: no repair).
  CHECK(std::equal(f.history.begin(), f.history.end(), History().end() - f.history.size()));
  const std::vector<float> s = f.Sequence(2);
  REQUIRE(s.size() == (f.history_frames + f.frames) * frame);
  CHECK(std::equal(f.history.begin(), f.history.end(), s.begin()));
  CHECK(std::equal(s.begin() + f.history.size(), s.end(), f.sample(2)));
  CHECK_THROWS_WITH(f.Sequence(3), Contains("expected a sample in [0, 3), got 3"));
}

TEST_CASE(
    "Model::WritePrediction writes what `motionfork predict` writes, ReadPrediction reads it") {
  const Tiny tiny;
  const Model model = tiny.Load();
  const PredictOptions options{4, 9, {"legs"}};
  const Futures f = model.Predict(History(), options);
  const std::string base = model.WritePrediction(tiny.dir.file("pred"), f, options);
  CHECK(base == tiny.dir.file("pred"));
  const Prediction p = ReadPrediction(base + ".json");
  CHECK(p.k == 4);
  CHECK(p.t_his == f.history_frames);
  CHECK(p.t_pred == f.frames);
  CHECK(p.seed == 9);
  CHECK(p.fixed_parts == std::vector<std::string>{"legs"});
  CHECK(p.skeleton->joint_names() == model.joint_names());
  REQUIRE(p.positions.size() == static_cast<size_t>(4 * (f.history_frames + f.frames) * 17 * 3));
  for (int k = 0; k < 4; ++k) {
    const std::vector<float> s = f.Sequence(k);
    CHECK(std::equal(s.begin(), s.end(), p.sample(k)));
  }
  Futures broken = f;
  broken.history.pop_back();
  CHECK_THROWS_WITH(model.WritePrediction(tiny.dir.file("bad"), broken),
                    Contains("expected futures from Model::Predict"));
  CHECK(!std::filesystem::exists(tiny.dir.file("bad.npy")));
}

TEST_CASE("Model::ExportBvh writes each sample as BVH that reads back to its positions") {
  const Tiny tiny;
  const Model model = tiny.Load();
  const Futures f = model.Predict(History(), {2, 1, {}});
  BvhExportOptions o;
  o.exact_lengths = true;
  const std::vector<std::string> paths = model.ExportBvh(tiny.dir.file("out.bvh"), f, o);
  REQUIRE(paths ==
          std::vector<std::string>{tiny.dir.file("out_00.bvh"), tiny.dir.file("out_01.bvh")});
  const Motion back = ReadMotionFile(paths[1]);
  const std::vector<float> s = f.Sequence(1);
  REQUIRE(back.positions().size() == s.size());
  float worst = 0;
  for (size_t i = 0; i < s.size(); ++i)
    worst = std::max(worst, std::abs(back.positions()[i] - s[i]));
  CHECK(worst < 1e-4f);
  o.sample = 1;
  CHECK(model.ExportBvh(tiny.dir.file("one.bvh"), f, o) ==
        std::vector<std::string>{tiny.dir.file("one.bvh")});
  CHECK_THROWS_WITH(model.ExportBvh(tiny.dir.file("x.txt"), f), Contains("ending in .bvh"));
}

TEST_CASE("Model::PriorNll: the shipped bundle's prior per frame, and a clear error without one") {
  LoadOptions options;
  options.config_dir = MOTIONFORK_CONFIG_DIR;
  const std::string dir = std::string(MOTIONFORK_SOURCE_DIR) + "/models/bandai";
  const Model shipped = Model::Load(dir, options);
  REQUIRE(shipped.has_prior());
  const auto skeleton =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "bandai")).skeleton;
  const Motion walk = MakeDemoWalk(skeleton);
  const std::vector<double> nll = shipped.PriorNll(walk.positions());
  REQUIRE(nll.size() == static_cast<size_t>(walk.num_frames()));
  // The same figures as the validator the command uses.
  const PoseValidator judge = PoseValidator::FromBundle(dir, skeleton, walk.fps());
  CHECK(nll == judge.PriorNll(walk.positions().data(), walk.num_frames()));

  const Tiny tiny;
  const Model model = tiny.Load();
  CHECK(!model.has_prior());
  CHECK_THROWS_AS(model.PriorNll(History()), std::logic_error);
  CHECK_THROWS_WITH(model.PriorNll(History()), Contains("carries no pose prior"));
}

TEST_CASE(
    "Model::CheckHistory and WritePrediction: a history in millimetres is doubted, its "
    "futures are not valid") {
  LoadOptions options;
  options.config_dir = MOTIONFORK_CONFIG_DIR;
  const std::string dir = std::string(MOTIONFORK_SOURCE_DIR) + "/models/bandai";
  const Model shipped = Model::Load(dir, options);
  const auto skeleton =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "bandai")).skeleton;
  const Motion walk = MakeDemoWalk(skeleton);
  const HistoryDoubts fine = shipped.CheckHistory(walk.positions());
  CHECK(fine.doubts.empty());
  CHECK(fine.window_score > fine.window_bound);  // the bundle's HG-VAE scored it
  CHECK(std::isfinite(shipped.prior_bound()));
  std::vector<float> mm = walk.positions();
  for (float& v : mm) v *= 1000;
  const HistoryDoubts off = shipped.CheckHistory(mm);
  REQUIRE_FALSE(off.doubts.empty());
  CHECK_THAT(off.doubts[0], Contains("scale: ") && Contains("millimetres"));

  // The prediction file written through the API carries the doubts; no future is valid.
  const testing::TempDir tmp;
  const std::string out = tmp.file("mm");
  const Futures f = shipped.Predict(mm, {});
  shipped.WritePrediction(out, f);
  const Prediction p = ReadPrediction(out + ".json");
  REQUIRE(p.history_check);
  CHECK(p.history_check->doubts == off.doubts);
  for (const SampleValidity& v : p.samples) {
    CHECK_FALSE(v.valid);
    CHECK_FALSE(v.history_ok);
  }
  REQUIRE(p.prior_bound);
  CHECK(*p.prior_bound == Approx(shipped.prior_bound()));
}

TEST_CASE("Imputer fills exactly the NaN values and keeps the observed ones") {
  testing::TempDir dir;
  testing::WriteTinyHgvaeBundle(dir.file("hgvae"), 5, 4);
  const Imputer imputer = Imputer::Load(dir.file("hgvae"));
  CHECK(imputer.window_frames() == 5);
  CHECK(imputer.fps() == 30.0);
  const int J = static_cast<int>(imputer.joint_names().size());
  std::vector<float> motion = testing::TinyBundleHistory(12).positions();
  REQUIRE(motion.size() == 12u * J * 3);
  std::vector<float> damaged = motion;
  const int hand = J - 1;
  for (int t = 4; t < 9; ++t) {
    for (int c = 0; c < 3; ++c) {
      damaged[(t * J + hand) * 3 + c] = std::numeric_limits<float>::quiet_NaN();
    }
  }
  const Imputed filled = imputer.Impute(damaged);
  CHECK(filled.missing_values == 15);
  REQUIRE(filled.positions.size() == damaged.size());
  double error = 0;
  for (size_t i = 0; i < damaged.size(); ++i) {
    REQUIRE(std::isfinite(filled.positions[i]));
    if (std::isnan(damaged[i])) {
      error = std::max(error, double(std::abs(filled.positions[i] - motion[i])));
    } else {
      REQUIRE(filled.positions[i] == damaged[i]);
    }
  }
  CHECK(error < 0.5);  // metres: a filled hand stays near the body
  CHECK_THROWS_WITH(imputer.Impute(std::vector<float>(7, 0.0f)),
                    Contains("expected [T, " + std::to_string(J) + ", 3] positions"));
}

TEST_CASE("Denoiser gives a motion of the same shape, the same for the same input") {
  testing::TempDir dir;
  testing::WriteTinyDvaeBundles(dir.file("dvae"), 3, 2);
  const Denoiser denoiser = Denoiser::Load(dir.file("dvae") + "/denoiser");
  const std::vector<float> motion = testing::TinyBundleHistory(20).positions();
  REQUIRE(denoiser.joint_names().size() * 3 * 20 == motion.size());
  const std::vector<float> a = denoiser.Denoise(motion);
  REQUIRE(a.size() == motion.size());
  for (float v : a) REQUIRE(std::isfinite(v));
  CHECK(a != motion);
  CHECK(denoiser.Denoise(motion) == a);
  std::vector<float> bad = motion;
  bad[5] = std::numeric_limits<float>::infinity();
  CHECK_THROWS_AS(denoiser.Denoise(bad), std::invalid_argument);
}
