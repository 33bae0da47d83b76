// The shipped Bandai model (models/bandai), run as users run it: the demo's synthetic walk gives
// valid, seed-determined futures with part control; on real test data it beats zero-velocity.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/prediction_file.h"
#include "run_motionfork.h"
#include "test_support.h"

using namespace motionfork;
using testing::Motionfork;
using testing::Run;

namespace {

const std::string kModel = std::string(MOTIONFORK_SOURCE_DIR) + "/models/bandai";

// Largest coordinate spread of the given joints across samples, over the future frames.
double Spread(const Prediction& p, const std::vector<int>& joints) {
  double worst = 0;
  for (int k = 1; k < p.k; ++k)
    for (int t = p.t_his; t < p.frames(); ++t)
      for (int j : joints)
        for (int c = 0; c < 3; ++c) {
          const size_t i = (static_cast<size_t>(t) * p.joints() + j) * 3 + c;
          worst = std::max(worst, std::abs(double(p.sample(k)[i]) - p.sample(0)[i]));
        }
  return worst;
}

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE(
    "shipped model: valid futures of the synthetic walk, same seed same futures, fixed legs") {
  testing::TempDir dir;
  REQUIRE(Motionfork("synth walk --frames 30 -o " + dir.file("walk.csv")).status == 0);
  const std::string common =
      "predict --model " + kModel + " --history " + dir.file("walk.csv") + " -k 50 ";
  Run r = Motionfork(common + "-o " + dir.file("a"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  // Every future inside the angle ranges; the prior's bound (its q99) rejects a few unusual poses
  // (4 of 50 on 2026-12-05).
  CHECK_THAT(r.output, Catch::Contains(" of 50 futures valid (angle ranges, prior NLL <= "));
  CHECK_THAT(r.output, !Catch::Contains("outside the angle ranges"));
  CHECK_THAT(r.output, Catch::Contains("history: no doubt"));
  REQUIRE(Motionfork(common + "-o " + dir.file("b")).status == 0);
  const Prediction a = ReadPrediction(dir.file("a.json")), b = ReadPrediction(dir.file("b.json"));
  CHECK(a.positions == b.positions);
  const auto count_valid = [](const Prediction& p) {
    int valid = 0;
    for (const SampleValidity& s : p.samples) {
      CHECK(s.violating_frames == 0);
      CHECK(s.history_ok);
      CHECK(s.valid == s.prior_ok);
      valid += s.valid;
    }
    return valid;
  };
  CHECK(count_valid(a) >= 45);

  r = Motionfork(common + "--fix legs -o " + dir.file("legs"));
  REQUIRE(r.status == 0);
  const Prediction legs = ReadPrediction(dir.file("legs.json"));
  const Partition& parts = legs.skeleton->GetPartition();
  CHECK(Spread(legs, parts.parts[0].joints) == 0.0);
  CHECK(Spread(legs, parts.parts[1].joints) > 0.05);  // metres: the upper bodies differ
  CHECK(count_valid(legs) >= 45);
}

TEST_CASE(
    "shipped model: on a sixth of the Bandai test split it beats zero-velocity, with almost no "
    "broken angle") {
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  testing::TempDir dir;
  // Every training clip (the multimodal sets need none, but the protocol reads the split) and
  // every sixth test clip.
  std::ifstream in(data + "/split.tsv");
  std::ofstream out(dir.file("split.tsv"));
  std::string line;
  int test = 0;
  while (std::getline(in, line)) {
    if (line.rfind("test\t", 0) == 0 && test++ % 6 != 5) continue;
    out << line << "\n";
  }
  out.close();
  const std::string common = "-q eval --protocol bandai --data " + data + " --split-file " +
                             dir.file("split.tsv") + " -k 50 --json ";
  Run r = Motionfork(common + dir.file("model.json") + " --model " + kModel);
  INFO(r.output);
  REQUIRE(r.status == 0);
  r = Motionfork(common + dir.file("zv.json") + " --baseline zero-velocity");
  REQUIRE(r.status == 0);
  const nlohmann::json m = ReadJson(dir.file("model.json")), z = ReadJson(dir.file("zv.json"));
  CHECK(m["windows"].get<int>() == z["windows"].get<int>());
  CHECK(m["windows"].get<int>() > 300);
  CHECK(m["ade"].get<double>() < z["ade"].get<double>() - 0.03);
  CHECK(m["fde"].get<double>() < z["fde"].get<double>() - 0.05);
  CHECK(m["apd"].get<double>() > 1.0);
  // The repair is best-effort (200 steps at most, PoseRepairStats::still_broken): with the model
  // shipped since 2026-12-02 one predicted frame of the whole test split's 7.6 million stays
  // outside a range (on this sixth a rate of 0.000001: one frame of 1.3 million); the raw
  // network breaks 28% of them.
  CHECK(m["angle_violation_rate"].get<double>() <=
        std::max(1e-5, 2 * z["angle_violation_rate_gt"].get<double>()));
}
