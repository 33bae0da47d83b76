// --threads N on the evaluations: windows shared by several threads give the same figures as one
// thread (each window or chunk has its own seed; the sums are taken in order). `eval` for the
// shipped model (LibTorch, fused kernels, angle repair, prior and angle scorers) and a baseline;
// `hgvae eval` and `dvae eval` (imputation, test-time optimisation, forecasting from repaired
// histories) for the shipped history-repair models.
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "run_motionfork.h"
#include "test_support.h"

using motionfork::testing::Motionfork;
using motionfork::testing::Run;

namespace {

// A report without its timings (the only part that may differ between runs).
nlohmann::json Figures(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  nlohmann::json j = nlohmann::json::parse(in);
  for (const char* timing :
       {"seconds", "regression_frames_per_s", "optimisation_frames_per_s", "refiner_frames_per_s"})
    j.erase(timing);
  return j;
}

// The figures `command --json DIR/NAME` writes (it must succeed).
nlohmann::json FiguresOf(const std::string& command, const motionfork::testing::TempDir& dir,
                         const std::string& name) {
  const Run r = Motionfork(command + " --json " + dir.file(name));
  INFO(r.output);
  REQUIRE(r.status == 0);
  return Figures(dir.file(name));
}

// Every training clip (the protocol reads the split) and every twelfth test clip of the Bandai
// split, as DIR/split.tsv.
std::string SmallSplit(const std::string& data, const motionfork::testing::TempDir& dir) {
  std::ifstream in(data + "/split.tsv");
  std::ofstream out(dir.file("split.tsv"));
  int test = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("test\t", 0) == 0 && test++ % 12 != 11) continue;
    out << line << "\n";
  }
  return dir.file("split.tsv");
}

// Runs `command --threads 1|2 --json DIR/N.json` and checks that both report the same figures.
void CheckSameFigures(const std::string& command, const motionfork::testing::TempDir& dir) {
  for (int threads : {1, 2}) {
    const Run r = Motionfork(command + " --threads " + std::to_string(threads) + " --json " +
                             dir.file(std::to_string(threads) + ".json"));
    INFO(r.output);
    REQUIRE(r.status == 0);
  }
  const nlohmann::json one = Figures(dir.file("1.json")), two = Figures(dir.file("2.json"));
  CHECK(one.dump() == two.dump());
}

// `eval` on the Bandai data with the small split in dir and K = 20, up to the predictor; "" when
// the data is not there.
std::string SmallEval(const motionfork::testing::TempDir& dir) {
  const std::string data = motionfork::testing::SharedDataDir("data/bandai");
  if (data.empty()) return "";
  return "-q eval --protocol bandai --data " + data + " --split " + SmallSplit(data, dir) +
         " -k 20 ";
}

}  // namespace

TEST_CASE("eval with 1 and 2 threads writes identical figures") {
  motionfork::testing::TempDir dir;
  const std::string common = SmallEval(dir);
  if (common.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  for (const std::string& predictor :
       {std::string("--model ") + MOTIONFORK_SOURCE_DIR + "/models/bandai",
        std::string("--baseline nn"), std::string("--baseline constant-velocity")}) {
    CheckSameFigures(common + predictor, dir);
    const nlohmann::json one = Figures(dir.file("1.json"));
    CHECK(one["windows"].get<int>() > 50);
    // Where the body goes, beside the protocol's figures (Bandai is Y up; its ankles by the rig).
    CHECK(one["root_figures"]["up"] == "y");
    CHECK(one["root_figures"]["feet"] == "Foot_R, Foot_L");
    CHECK(one["root"]["fde"].get<double>() > 0);
    CHECK(one["root"]["foot_skating_gt"].get<double>() >= 0);
  }
}

TEST_CASE("hgvae eval and dvae eval with 1 and 2 threads write identical figures") {
  const std::string data = motionfork::testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  motionfork::testing::TempDir dir;
  const std::string models = std::string(MOTIONFORK_SOURCE_DIR) + "/models/bandai";
  const std::string common = " --data " + data + " --split " + SmallSplit(data, dir) +
                             " --forecaster " + models + " -k 5 --forecast-windows 12";
  SECTION("hgvae eval: likelihood, imputation (several chunks), OoD, forecasting") {
    CheckSameFigures(
        "-q hgvae eval --model " + models + "/hgvae --windows 100 --gap-clips 3" + common, dir);
    CHECK(Figures(dir.file("1.json"))["windows"].get<int>() == 100);
    // Forecasting also from the histories filled by the classical fills and the refiner.
    const nlohmann::json row = Figures(dir.file("1.json"))["forecasting"]["settings"][0];
    for (const char* key : {"ade_linear", "ade_spline", "fde_rigid_limb", "ade_refiner"})
      CHECK(row.contains(key));
    // One forecasting row alone: the same figures as in the run of all (the same masks).
    const nlohmann::json all = Figures(dir.file("1.json"))["forecasting"]["settings"];
    const nlohmann::json only =
        FiguresOf("-q hgvae eval --model " + models +
                      "/hgvae --windows 10 --gap-clips 0 --threads 2 --forecast-occlusion "
                      "'random 50%'" +
                      common,
                  dir, "one.json")["forecasting"]["settings"];
    REQUIRE(only.size() == 1);
    for (const auto& r : all)
      if (r["occlusion"] == "random 50%") CHECK(r.dump() == only[0].dump());
    const Run bad =
        Motionfork("-q hgvae eval --model " + models +
                   "/hgvae --windows 10 --gap-clips 0 --forecast-occlusion 'left ear'" + common);
    CHECK(bad.status == 2);
    CHECK_THAT(bad.output, Catch::Contains("no forecasting occlusion 'left ear'") &&
                               Catch::Contains("'random 50%'"));
    const Run no_forecaster =
        Motionfork("-q hgvae eval --model " + models + "/hgvae --data " + data + " --split " +
                   dir.file("split.tsv") + " --windows 10 --forecast-occlusion 'random 50%'");
    CHECK(no_forecaster.status == 2);
    CHECK_THAT(no_forecaster.output, Catch::Contains("no forecaster was given"));
    // The test clips played twice as slow: twice the frames, so twice the windows of the split
    // (counted by the likelihood alone); the forecasting rows run on them too.
    auto windows = [&](const std::string& slow, const std::string& file) {
      const nlohmann::json j = FiguresOf(
          "-q hgvae eval --model " + models + "/hgvae --windows 100000 --likelihood-only" + slow +
              " --data " + data + " --split " + dir.file("split.tsv"),
          dir, file);
      CHECK(j.contains("slow") == !slow.empty());
      return j["windows"].get<int>();
    };
    const int w2 = windows(" --slow 2", "slow.json"), w1 = windows("", "normal.json");
    CHECK(w2 >= 2 * w1 - 10);
    CHECK(w2 <= 2 * w1 + 10);
    const nlohmann::json slow = FiguresOf(
        "-q hgvae eval --model " + models +
            "/hgvae --windows 10 --gap-clips 0 --slow 2 --forecast-occlusion 'random 50%'" + common,
        dir, "slow_forecast.json");
    CHECK(slow["slow"].get<double>() == 2);
    CHECK(slow["forecasting"]["settings"][0]["fde_refiner"].get<double>() > 0);
  }
  SECTION("dvae eval: regression and optimisation modes, forecasting") {
    CheckSameFigures(
        "-q dvae eval --model " + models +
            "/dvae --test-clips 4 --optimisation-clips 2 --tuning-clips 5 --noise gaussian:0.05 "
            "--noise outliers:0.1,0.3" +
            common,
        dir);
    const nlohmann::json as_recorded = Figures(dir.file("1.json"));
    CHECK(as_recorded["optimisation_clips"].get<int>() == 2);
    // The test clips played twice as slow: about twice the frames, a quarter of the acceleration.
    const nlohmann::json j = FiguresOf("-q dvae eval --model " + models +
                                           "/dvae --test-clips 4 --optimisation-clips 0 "
                                           "--tuning-clips 5 --noise gaussian:0.05 --slow 2" +
                                           common,
                                       dir, "slow.json");
    CHECK(j["slow"].get<double>() == 2);
    CHECK(j["frames"].get<int>() == 2 * as_recorded["frames"].get<int>() - 4);
    CHECK(j["clean_accel"].get<double>() ==
          Approx(as_recorded["clean_accel"].get<double>() / 4).epsilon(0.1));
  }
}

TEST_CASE("eval --turn turns the test clips: a baseline blind to heading keeps its figures") {
  motionfork::testing::TempDir dir;
  const std::string common = SmallEval(dir);
  if (common.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  auto figures = [&](const std::string& args, const std::string& name) {
    return FiguresOf(common + args, dir, name);
  };
  // Zero velocity repeats the last pose: turned clips give the same distances, so the same
  // figures. Nearest neighbours match turned histories against the training clips as recorded,
  // which face the capture room's way: other neighbours, other figures.
  const nlohmann::json zv = figures("--baseline zero-velocity", "zv.json");
  const nlohmann::json zv90 = figures("--baseline zero-velocity --turn 90", "zv90.json");
  CHECK(zv90["turn_degrees"].get<double>() == 90);
  for (const char* m : {"ade", "fde", "mmade", "mmfde"})
    CHECK(zv90[m].get<double>() == Approx(zv[m].get<double>()).epsilon(1e-5));
  CHECK(zv90["root"]["fde"].get<double>() == Approx(zv["root"]["fde"].get<double>()).epsilon(1e-5));
  const nlohmann::json nn = figures("--baseline nn", "nn.json");
  const nlohmann::json nn90 = figures("--baseline nn --turn 90", "nn90.json");
  CHECK(nn90["fde"].get<double>() > nn["fde"].get<double>() + 0.01);
  const Run bad = Motionfork(common + "--baseline zero-velocity --turn nan");
  CHECK(bad.status == 2);
}
