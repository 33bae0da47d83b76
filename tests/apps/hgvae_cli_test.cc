// motionfork impute / ood / hgvae sample / predict --impute end to end, on a tiny HG-VAE trained
// in code (tests/imputation/tiny_hgvae.h) and the tiny generator bundle (tests/api/tiny_bundle.h).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "api/tiny_bundle.h"
#include "imputation/tiny_hgvae.h"
#include "io/csv.h"
#include "io/motion_file.h"
#include "io/npy.h"
#include "io/prediction_file.h"
#include "run_motionfork.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;
using testing::Motionfork;
using testing::Run;

namespace {

namespace fs = std::filesystem;

// One tiny HG-VAE (window 5 = the tiny generator's history) and generator bundle for the file.
struct Models {
  testing::TempDir dir;
  std::string hgvae = dir.file("hgvae"), generator = dir.file("generator");
  Models() {
    testing::WriteTinyHgvaeBundle(hgvae, 5, 4);
    testing::WriteTinyBundle(generator, MOTIONFORK_CONFIG_DIR);
  }
};
const Models& SharedModels() {
  static Models m;
  return m;
}

// A walk with Hand_L's x missing (NaN) in frames 3..6, as .npy.
std::string WalkWithNaN(const testing::TempDir& dir, int frames = 12) {
  const Motion m = testing::TinyBundleHistory(frames);
  NpyArray a{{frames, 17, 3}, m.positions()};
  for (int t = 3; t <= 6 && t < frames; ++t)
    a.data[(t * 17 + 13) * 3] = std::numeric_limits<float>::quiet_NaN();
  const std::string path = dir.file("nan.npy");
  // WriteNpy refuses NaN: serialise finite values, then put the NaNs into the bytes.
  std::string bytes = SerializeNpy(NpyArray{a.shape, m.positions()});
  const size_t header = bytes.size() - a.data.size() * 4;
  for (size_t i = 0; i < a.data.size(); ++i) std::memcpy(&bytes[header + 4 * i], &a.data[i], 4);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

}  // namespace

TEST_CASE("impute: NaN values and --mask joints are filled, observed values kept, file written") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  const std::string in = WalkWithNaN(dir);
  Run r = Motionfork("impute --model " + models.hgvae + " --motion " + in +
                     " --skeleton bandai --fps 30 --mask " + "joints:Head@0-2 -o " +
                     dir.file("out.npy"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("imputed 13 of 612 values"));
  const NpyArray out = ReadNpy(dir.file("out.npy"));
  const Motion truth = testing::TinyBundleHistory(12);
  for (size_t i = 0; i < out.data.size(); ++i) {
    const size_t t = i / 51, j = (i % 51) / 3, a = i % 3;
    const bool was_missing = (j == 13 && a == 0 && t >= 3 && t <= 6) || (j == 10 && t <= 2);
    if (!was_missing) CHECK(out.data[i] == truth.positions()[i]);
    CHECK(std::isfinite(out.data[i]));
  }
}

TEST_CASE("impute: bad masks and all-missing windows are refused with the file named") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  WriteCsvMotion(dir.file("walk.csv"), testing::TinyBundleHistory(12));
  const std::string base = "impute --model " + models.hgvae + " --motion " + dir.file("walk.csv") +
                           " -o " + dir.file("o.csv");
  Run r = Motionfork(base + " --mask joints:Nose");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("walk.csv") && Contains("Nose") && Contains("Hand_L"));
  r = Motionfork(base + " --mask joints:Head@3-40");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("0..11"));
  r = Motionfork(base + " --mask random:1.0");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("every value is missing"));
  CHECK_FALSE(fs::exists(dir.file("o.csv")));
  r = Motionfork(base + " --mask joints:Hips");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("root"));
}

TEST_CASE("ood: scores every window, exit status 1 only when one is flagged") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  WriteCsvMotion(dir.file("walk.csv"), testing::MakeWalkingMotion(15, 30.0, 101));
  Run r = Motionfork("ood --model " + models.hgvae + " --motion " + dir.file("walk.csv") +
                     " --json " + dir.file("s.json"));
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("0 of 3 windows out of distribution"));
  CHECK(fs::exists(dir.file("s.json")));
  // Bones three times as long: no such body in the training data.
  Motion walk = testing::MakeWalkingMotion(15, 30.0, 101);
  std::vector<float> p = walk.positions();
  for (size_t i = 0; i < p.size(); ++i)
    p[i] = 3.0f * (p[i] - p[(i / 51) * 51 + i % 3]) + p[(i / 51) * 51 + i % 3];
  WriteCsvMotion(dir.file("giant.csv"), Motion(walk.skeleton_ptr(), 30, p));
  r = Motionfork("ood --model " + models.hgvae + " --motion " + dir.file("giant.csv"));
  CHECK(r.status == 1);
  CHECK_THAT(r.output, Contains("3 of 3 windows out of distribution"));
}

TEST_CASE("hgvae sample: writes motion windows, same seed same file") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  for (const char* name : {"a.npy", "b.npy"}) {
    Run r =
        Motionfork("hgvae sample --model " + models.hgvae + " -n 3 --seed 2 -o " + dir.file(name));
    INFO(r.output);
    REQUIRE(r.status == 0);
  }
  const NpyArray a = ReadNpy(dir.file("a.npy")), b = ReadNpy(dir.file("b.npy"));
  CHECK(a.shape == std::vector<int64_t>{15, 17, 3});
  CHECK(a.data == b.data);
  Run r =
      Motionfork("hgvae sample --model " + models.hgvae + " --class walk -o " + dir.file("c.npy"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("unconditional"));
}

TEST_CASE("predict --impute: a history with missing values is imputed, then forecast") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  const std::string in = WalkWithNaN(dir, 8);  // history = frames 3..7: Hand_L x missing in 3..6
  Run r = Motionfork("predict --model " + models.generator + " --history " + in +
                     " --skeleton bandai --fps 30 -k 4 -o " + dir.file("p"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("4 missing values") && Contains("--impute"));
  r = Motionfork("predict --model " + models.generator + " --history " + in +
                 " --skeleton bandai --fps 30 -k 4 --impute " + models.hgvae + " -o " +
                 dir.file("p"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("imputed 4 missing history values"));
  const Prediction p = ReadPrediction(dir.file("p.json"));
  REQUIRE(p.imputation.has_value());
  CHECK(p.imputation->missing_values == 4);
  for (float v : p.positions) CHECK(std::isfinite(v));
  // --mask without --impute is refused.
  r = Motionfork("predict --model " + models.generator + " --history " + in +
                 " --skeleton bandai -k 4 --mask joints:Head -o " + dir.file("q"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("--mask needs --impute"));
}

TEST_CASE("ood: the header names the threshold, the motion first, --motion deprecated") {
  const Models& models = SharedModels();
  testing::TempDir dir;
  WriteCsvMotion(dir.file("walk.csv"), testing::MakeWalkingMotion(15, 30.0, 101));
  Run now = Motionfork("ood " + dir.file("walk.csv") + " --model " + models.hgvae + " --json -");
  INFO(now.output);
  CHECK(now.status == 0);
  CHECK_THAT(now.output, Contains("out of distribution (threshold "));
  CHECK_THAT(now.output, Contains("\"flagged\": 0"));
  Run old = Motionfork("ood --model " + models.hgvae + " --motion " + dir.file("walk.csv"));
  CHECK(old.status == 0);
  CHECK_THAT(old.output, Contains("--motion is deprecated"));
  CHECK_THAT(old.output, Contains("0 of 3 windows out of distribution"));
}
