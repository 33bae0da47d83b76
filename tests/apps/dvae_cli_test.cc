// motionfork denoise / dvae eval / predict --denoise end to end, on a tiny Motion-DVAE trained in
// code (tests/denoise/tiny_dvae.h) and the tiny generator bundle (tests/api/tiny_bundle.h).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "api/tiny_bundle.h"
#include "core/motion_noise.h"
#include "denoise/denoise_metrics.h"
#include "denoise/tiny_dvae.h"
#include "io/csv.h"
#include "io/motion_file.h"
#include "io/prediction_file.h"
#include "run_motionfork.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;
using testing::Motionfork;
using testing::Run;

namespace {

namespace fs = std::filesystem;

struct Models {
  testing::TempDir dir;
  std::string denoiser = dir.file("dvae/denoiser"), generator = dir.file("generator");
  Models() {
    testing::WriteTinyDvaeBundles(dir.file("dvae"), 3, 2);
    testing::WriteTinyBundle(generator, MOTIONFORK_CONFIG_DIR);
  }
};
const Models& SharedModels() {
  static Models m;
  return m;
}

}  // namespace

TEST_CASE("denoise: writes a denoised file of the same length, deterministic, and reports speed") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  const Motion clean = testing::MakeWalkingMotion(40, 30, 77);
  WriteCsvMotion(dir.file("noisy.csv"), AddNoise(clean, ParseNoiseSpec("gaussian:0.05"), 1));
  const std::string base = "denoise --model " + models.denoiser + " --motion " +
                           dir.file("noisy.csv") + " --skeleton bandai";
  Run r = Motionfork(base + " -o " + dir.file("a.csv"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output,
             Contains("denoised 40 frames") && Contains("frames/s") && Contains("Hand_R"));
  REQUIRE(Motionfork(base + " -o " + dir.file("b.csv")).status == 0);
  const Motion a = ReadMotionFile(dir.file("a.csv")), b = ReadMotionFile(dir.file("b.csv"));
  CHECK(a.num_frames() == 40);
  CHECK(a.positions() == b.positions());
  const Motion noisy = ReadMotionFile(dir.file("noisy.csv"));
  CHECK(MeanJointError(a.positions(), noisy.positions()) > 0.001);
  r = Motionfork(base + " --mode optimisation --iterations 2 --samples 0 -o " + dir.file("c.csv"));
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("optimisation mode, 2 iterations"));
  // --add-noise: the error against the file as read is reported.
  WriteCsvMotion(dir.file("clean.csv"), clean);
  r = Motionfork("denoise --model " + models.denoiser + " --motion " + dir.file("clean.csv") +
                 " --skeleton bandai --add-noise jitter:0.05 -o " + dir.file("d.csv"));
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("added jitter:0.05 noise") &&
                           Contains("against the file before --add-noise: noisy"));
}

TEST_CASE("denoise: bad input is refused with the file named and nothing written") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  WriteCsvMotion(dir.file("walk.csv"), testing::MakeWalkingMotion(20));
  const std::string base = "denoise --model " + models.denoiser + " --motion " +
                           dir.file("walk.csv") + " --skeleton bandai";
  Run r = Motionfork(base + " --add-noise gaussian:x -o " + dir.file("o.csv"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("--add-noise") && Contains("not a number"));
  r = Motionfork("denoise --model " + models.denoiser + " --motion " + dir.file("walk.csv") +
                 " --skeleton bandai --mode magic -o " + dir.file("o.csv"));
  CHECK(r.status != 0);
  r = Motionfork("denoise --model " + dir.path().string() + " --motion " + dir.file("walk.csv") +
                 " -o " + dir.file("o.csv"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("dvae.yaml"));
  CHECK_FALSE(fs::exists(dir.file("o.csv")));
}

TEST_CASE("predict --denoise: the history is denoised before forecasting and the JSON says so") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  const Motion noisy = AddNoise(testing::TinyBundleHistory(12), ParseNoiseSpec("gaussian:0.03"), 2);
  WriteCsvMotion(dir.file("h.csv"), noisy);
  const std::string base =
      "predict --model " + models.generator + " --history " + dir.file("h.csv") + " -k 4 --seed 1";
  Run r = Motionfork(base + " --denoise " + models.denoiser + " -o " + dir.file("d"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("denoised the history"));
  const Prediction d = ReadPrediction(dir.file("d.json"));
  REQUIRE(d.denoising.has_value());
  CHECK(d.denoising->mode == "regression");
  CHECK(d.denoising->mean_change > 0);
  REQUIRE(Motionfork(base + " -o " + dir.file("n")).status == 0);
  const Prediction n = ReadPrediction(dir.file("n.json"));
  CHECK_FALSE(n.denoising.has_value());
  CHECK(n.positions != d.positions);
}

TEST_CASE("dvae train, finetune and refine chain on a data folder into a bundle that denoises") {
  testing::TempDir dir;
  const std::string data = dir.file("data"), config = dir.file("tiny.yaml");
  fs::create_directories(data);
  std::string split;
  for (int c = 0; c < 4; ++c) {
    const std::string clip = "walk_" + std::to_string(c) + ".bvh";
    REQUIRE(Motionfork("synth walk --frames 90 --heading " + std::to_string(40 * c) + " -o " +
                       data + "/" + clip)
                .status == 0);
    split += std::string(c < 3 ? "train\t" : "test\t") + clip + "\n";
  }
  std::ofstream(data + "/split.tsv") << split;
  std::ofstream(config) << R"(name: tiny-dvae-cli
protocol: bandai
model: {window: 10, hidden: 16, latent: 4, mlp_hidden: 16, groups: 4}
training: {epochs: 1, windows_per_epoch: 64, batch_size: 32, held_out_share: 0.3, held_out_windows: 8}
finetune: {epochs: 1, windows_per_epoch: 64, batch_size: 32}
refiner: {channels: 8, window: 20, stride: 5, dilations: [1, 2], linear_reach: 3, epochs: 2,
          windows_per_epoch: 64, batch_size: 32}
)";
  const std::string common = " --config " + config + " --data " + data;
  Run r = Motionfork("-q dvae train" + common + " --out " + dir.file("prior"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("next: motionfork dvae finetune --prior " + dir.file("prior")));
  r = Motionfork("-q dvae finetune" + common + " --prior " + dir.file("prior") + " --out " +
                 dir.file("denoiser"));
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("next: motionfork dvae refine"));
  r = Motionfork("-q dvae refine" + common + " --prior " + dir.file("denoiser") + " --out " +
                 dir.file("refined"));
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("supervised refiner training") && Contains("trained epochs 1..2") &&
                           Contains("denoise mode refiner"));
  r = Motionfork("denoise --model " + dir.file("refined") + " " + data + "/walk_3.bvh -o " +
                 dir.file("out.npy") + " --add-noise gaussian:0.05");
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("refiner mode") && Contains("windows of <= 20 frames"));
  CHECK(fs::exists(dir.file("out.npy")));
  // Without --prior the stage cannot start, and says so.
  r = Motionfork("-q dvae refine" + common + " --out " + dir.file("x"));
  CHECK(r.status != 0);
  CHECK_THAT(r.output, Contains("--prior"));
}
