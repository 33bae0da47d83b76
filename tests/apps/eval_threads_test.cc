// `motionfork eval --threads N`: the test windows measured on several threads give the same figures
// as one thread (each window has its own seed; the sums are taken in window order), for the
// shipped model (LibTorch, fused kernels, angle repair, prior and angle scorers) and a baseline.
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
  j.erase("seconds");
  return j;
}

}  // namespace

TEST_CASE("eval with 1 and 2 threads writes identical figures") {
  const std::string data = motionfork::testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  motionfork::testing::TempDir dir;
  // Every training clip (the protocol reads the split) and every twelfth test clip.
  std::ifstream in(data + "/split.tsv");
  std::ofstream out(dir.file("split.tsv"));
  int test = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("test\t", 0) == 0 && test++ % 12 != 11) continue;
    out << line << "\n";
  }
  out.close();
  const std::string common = "-q eval --protocol bandai --data " + data + " --split-file " +
                             dir.file("split.tsv") + " -k 20 ";
  for (const std::string& predictor :
       {std::string("--model ") + MOTIONFORK_SOURCE_DIR + "/models/bandai",
        std::string("--baseline nn")}) {
    for (int threads : {1, 2}) {
      const Run r = Motionfork(common + predictor + " --threads " + std::to_string(threads) +
                               " --json " + dir.file(std::to_string(threads) + ".json"));
      INFO(r.output);
      REQUIRE(r.status == 0);
    }
    const nlohmann::json one = Figures(dir.file("1.json")), two = Figures(dir.file("2.json"));
    CHECK(one["windows"].get<int>() > 50);
    CHECK(one.dump() == two.dump());
  }
}
