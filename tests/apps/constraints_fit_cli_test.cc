// `motionfork constraints fit --leave-one-out` on a folder of synthetic walks in three "styles"
// (Bandai file names: dataset-2_walk_<style>_<id>.bvh; slow, middle and fast gaits): each style is
// left out of the fit in turn and its frames checked against the ranges of the other two.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/file_util.h"
#include "run_motionfork.h"
#include "test_support.h"

using motionfork::testing::Motionfork;
using motionfork::testing::Run;

namespace {

// The share printed in the left-out table's row for `style`, or -1 when there is no such row.
double FlaggedShare(const std::string& output, const std::string& style) {
  const size_t table = output.find("leave one subject out");
  if (table == std::string::npos) return -1;
  const size_t row = output.find("\n" + style + " ", table);
  if (row == std::string::npos) return -1;
  const size_t percent = output.find('%', row);
  size_t start = output.rfind(' ', percent);
  return std::stod(output.substr(start + 1, percent - start - 1));
}

}  // namespace

TEST_CASE("constraints fit --leave-one-out: each style's frames against the others' ranges") {
  motionfork::testing::TempDir dir;
  const std::string data = dir.file("data");
  std::filesystem::create_directories(data);
  std::ofstream split(data + "/split.tsv");
  struct Style {
    const char* name;
    const char* speed;
    const char* stride_hz;
  };
  for (const Style& s :
       {Style{"slow", "0.6", "0.6"}, Style{"mid", "1.2", "0.9"}, Style{"fast", "2.4", "1.3"}}) {
    for (int id = 1; id <= 2; ++id) {
      const std::string clip =
          std::string("dataset-2_walk_") + s.name + "_00" + std::to_string(id) + ".bvh";
      const Run r = Motionfork(std::string("synth walk --frames 120 --speed ") + s.speed +
                               " --stride-hz " + s.stride_hz + " --heading " +
                               std::to_string(50 * id) + " -o " + data + "/" + clip);
      REQUIRE(r.status == 0);
      split << "train\t" << clip << "\n";
    }
  }
  split.close();
  // The shipped definitions without their literature limits, so that only the data decides.
  std::ifstream shipped(std::string(MOTIONFORK_CONFIG_DIR) + "/constraints/bandai.yaml");
  std::ofstream plain(dir.file("plain.yaml"));
  for (std::string line; std::getline(shipped, line);)
    if (line.find("anatomical:") == std::string::npos) plain << line << "\n";
  plain.close();
  const std::string fit = "-q constraints fit --protocol bandai --data " + data + " --split " +
                          data + "/split.tsv --constraints " + dir.file("plain.yaml");

  // No margin: the fast gait bends its knees beyond what the slower two do.
  const Run tight =
      Motionfork(fit + " -o " + dir.file("tight.yaml") + " --leave-one-out --margin 0 --round 0");
  INFO(tight.output);
  REQUIRE(tight.status == 0);
  const double fast_tight = FlaggedShare(tight.output, "fast");
  CHECK(fast_tight > 5);
  CHECK(FlaggedShare(tight.output, "slow") >= 0);
  CHECK(FlaggedShare(tight.output, "mid") >= 0);
  const std::string header = motionfork::ReadFileBytes(dir.file("tight.yaml"));
  CHECK(header.find("--leave-one-out") != std::string::npos);
  CHECK(header.find("Each of the 3 training subjects left out in turn") != std::string::npos);

  // The default margin covers more of what the others did not show.
  const Run wide = Motionfork(fit + " -o " + dir.file("wide.yaml") + " --leave-one-out");
  INFO(wide.output);
  REQUIRE(wide.status == 0);
  CHECK(FlaggedShare(wide.output, "fast") < fast_tight);

  // One style is not enough to leave one out.
  std::ofstream(dir.file("one.tsv")) << "train\tdataset-2_walk_slow_001.bvh\n"
                                     << "train\tdataset-2_walk_slow_002.bvh\n";
  const Run one =
      Motionfork("-q constraints fit --protocol bandai --data " + data + " --split " +
                 dir.file("one.tsv") + " -o " + dir.file("one.yaml") + " --leave-one-out");
  CHECK(one.status == 2);
  CHECK(one.output.find("at least two subjects") != std::string::npos);
  CHECK(one.output.find("('slow')") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir.file("one.yaml")));
}
