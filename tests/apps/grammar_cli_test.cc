// One grammar for the command line: global options anywhere, typo suggestions, deprecated
// spellings that still work (with a note on stderr), --json [FILE] in both of its forms.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "io/csv.h"
#include "io/file_util.h"
#include "run_motionfork.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;
using testing::Motionfork;
using testing::Run;

namespace {

// stdout only; stderr goes to `stderr_file`.
Run Stdout(const std::string& args, const std::string& stderr_file) {
  return testing::RunShell(std::string(MOTIONFORK_BINARY) + " --cache-dir none " + args + " 2>" +
                           stderr_file);
}

// The last line of an output (where a one-line JSON report printed after the text is).
std::string LastLine(const std::string& text) {
  const size_t end = text.find_last_not_of('\n');
  const size_t start = text.rfind('\n', end);
  return text.substr(start == std::string::npos ? 0 : start + 1, end + 1 - (start + 1));
}

}  // namespace

TEST_CASE("global options after the subcommand, typo suggestions") {
  testing::TempDir dir;
  Run r = Motionfork("synth walk -o " + dir.file("w.csv") + " --quiet");
  INFO(r.output);
  CHECK(r.status == 0);
  r = Motionfork("info " + dir.file("w.csv") + " --quiet");
  CHECK(r.status == 0);
  r = Motionfork("predcit --model x");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("did you mean 'predict'"));
}

TEST_CASE("deprecated spellings give the same output as the new ones, with a note") {
  testing::TempDir dir;
  REQUIRE(Motionfork("synth walk --frames 30 -o " + dir.file("w.csv")).status == 0);
  // A typed option: render --samples N is --count N.
  const std::string render = "render " + dir.file("w.csv") + " -o " + dir.file("w.svg");
  const Run now = Stdout(render + " --count 1", dir.file("now.err"));
  const Run old = Stdout(render + " --samples 1", dir.file("old.err"));
  REQUIRE(now.status == 0);
  CHECK(old.output == now.output);
  CHECK(ReadFileBytes(dir.file("now.err")).find("deprecated") == std::string::npos);
  CHECK_THAT(ReadFileBytes(dir.file("old.err")),
             Contains("--samples is deprecated, write --count instead"));

  // A string option: eval --split-file FILE is --split FILE; --split NAME is --subset NAME.
  const std::string data = dir.file("data");
  std::filesystem::create_directories(data);
  int heading = 0;
  for (const char* clip : {"walk_a", "walk_b", "walk_c"}) {
    REQUIRE(Motionfork("synth walk --frames 160 --heading " + std::to_string(heading += 40) +
                       " -o " + data + "/" + clip + ".bvh")
                .status == 0);
  }
  std::ofstream(dir.file("split.tsv"))
      << "train\twalk_a.bvh\ntrain\twalk_b.bvh\ntest\twalk_c.bvh\n";
  const std::string eval =
      "-q eval --protocol bandai --data " + data + " --baseline zero-velocity -k 2 --json - ";
  const Run e_now =
      Stdout(eval + "--split " + dir.file("split.tsv") + " --subset test", dir.file("e_now.err"));
  INFO(e_now.output << ReadFileBytes(dir.file("e_now.err")));
  REQUIRE(e_now.status == 0);
  const Run e_old = Stdout(eval + "--split-file " + dir.file("split.tsv") + " --split test",
                           dir.file("e_old.err"));
  REQUIRE(e_old.status == 0);
  const auto a = nlohmann::json::parse(LastLine(e_now.output));
  const auto b = nlohmann::json::parse(LastLine(e_old.output));
  CHECK(a["windows"] == b["windows"]);
  CHECK(a["ade"] == b["ade"]);
  CHECK(a["split"] == "test");
  const std::string note = ReadFileBytes(dir.file("e_old.err"));
  CHECK_THAT(note, Contains("--split-file is deprecated, write --split FILE instead"));
  CHECK_THAT(note, Contains("--split test is deprecated, write --subset test instead"));
}

TEST_CASE("json reports: --json FILE writes the report there, --json - prints it") {
  testing::TempDir dir;
  WriteCsvMotion(dir.file("walk.csv"), testing::MakeWalkingMotion(40, 30.0));
  // Formerly a flag (info): a FILE now writes the report there, and the text still prints.
  Run r = Motionfork("info " + dir.file("walk.csv") + " --json " + dir.file("info.json"));
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("40 at 30 Hz"));
  std::ifstream in(dir.file("info.json"));
  CHECK(nlohmann::json::parse(in)["frames"] == 40);
  r = Motionfork("info " + dir.file("walk.csv") + " --json -");
  CHECK(nlohmann::json::parse(r.output)["frames"] == 40);

  // Formerly "write FILE" (dataset stats): '-' prints it after the text.
  const std::string data = dir.file("data");
  std::filesystem::create_directories(data);
  REQUIRE(Motionfork("synth walk --frames 160 -o " + data + "/walk_a.bvh").status == 0);
  std::ofstream(dir.file("split.tsv")) << "train\twalk_a.bvh\n";
  const std::string stats =
      "dataset stats --protocol bandai --data " + data + " --split " + dir.file("split.tsv");
  r = Stdout(stats + " --json -", dir.file("err"));
  REQUIRE(r.status == 0);
  CHECK(nlohmann::json::parse(LastLine(r.output))["train"]["clips"] == 1);
  r = Motionfork(stats + " --json " + dir.file("stats.json"));
  REQUIRE(r.status == 0);
  std::ifstream stats_in(dir.file("stats.json"));
  CHECK(nlohmann::json::parse(stats_in)["train"]["frames"] == 160);
}
