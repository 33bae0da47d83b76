// The motionfork command, run as users run it: help, exit statuses, info/convert/dataset stats.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "io/csv.h"
#include "io/file_util.h"
#include "io/npy.h"
#include "run_motionfork.h"
#include "test_support.h"

using namespace motionfork;

using testing::Motionfork;
using testing::Run;

TEST_CASE("every subcommand has --help") {
  for (const char* sub :
       {"", "info", "convert", "dataset", "dataset stats", "train", "predict", "eval", "prior",
        "prior train", "prior score", "prior sample", "check", "constraints", "constraints fit",
        "constraints show", "export", "render", "synth"}) {
    const Run r = Motionfork(std::string(sub) + " --help");
    INFO(sub << ": " << r.output);
    CHECK(r.status == 0);
    CHECK(r.output.find("Usage") != std::string::npos);
  }
}

TEST_CASE("info and convert work on npy and csv, onto a named skeleton") {
  testing::TempDir dir;
  const Motion m = testing::MakeWalkingMotion(40, 30.0);
  WriteCsvMotion(dir.file("walk.csv"), m);
  Run r = Motionfork("info " + dir.file("walk.csv"));
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(r.output.find("40 at 30 Hz") != std::string::npos);
  CHECK(r.output.find("17 joints") != std::string::npos);

  r = Motionfork("convert " + dir.file("walk.csv") + " " + dir.file("walk.npy") +
                 " --skeleton bandai");
  CHECK(r.status == 0);
  const NpyArray a = ReadNpy(dir.file("walk.npy"));
  CHECK(a.shape == std::vector<int64_t>{40, 17, 3});
  // Converted onto the bandai protocol skeleton: same joints, same values.
  CHECK(a.data == m.positions());

  r = Motionfork("info " + dir.file("walk.npy") + " --skeleton bandai --fps 30 --json");
  CHECK(r.status == 0);
  CHECK(r.output.find("\"frames\": 40") != std::string::npos);
  CHECK(r.output.find("\"parents\": [-1, 0, 1, 2, 0, 4, 5, 0, 7, 8, 9, 8, 11, 12, 8, 14, 15]") !=
        std::string::npos);

  r = Motionfork("convert " + dir.file("walk.npy") + " " + dir.file("half.csv") +
                 " --skeleton bandai --fps 30 --resample 15");
  CHECK(r.status == 0);
  CHECK(r.output.find("20 frames at 15 Hz") != std::string::npos);
  // The output as -o, the grammar of the other commands, gives the same file.
  r = Motionfork("convert " + dir.file("walk.npy") + " -o " + dir.file("half2.csv") +
                 " --skeleton bandai --fps 30 --resample 15");
  CHECK(r.status == 0);
  CHECK(ReadFileBytes(dir.file("half2.csv")) == ReadFileBytes(dir.file("half.csv")));
}

TEST_CASE("bad input exits with status 2 and names the file") {
  testing::TempDir dir;
  std::ofstream(dir.file("bad.csv")) << "Hips.x,Hips.y,Hips.z\n0,1,oops\n";
  Run r = Motionfork("info " + dir.file("bad.csv"));
  CHECK(r.status == 2);
  CHECK(r.output.find("bad.csv") != std::string::npos);
  CHECK(r.output.find("line 2") != std::string::npos);

  r = Motionfork("info " + dir.file("missing.bvh"));
  CHECK(r.status == 2);

  WriteNpyMotion(dir.file("m.npy"), testing::MakeWalkingMotion(5));
  r = Motionfork("info " + dir.file("m.npy") + " --skeleton humaneva");
  CHECK(r.status == 2);
  CHECK(r.output.find("17 unnamed joints") != std::string::npos);

  r = Motionfork("convert " + dir.file("m.npy") + " " + dir.file("out.txt"));
  CHECK(r.status == 2);
  CHECK(r.output.find("unknown motion format") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir.file("out.txt")));

  r = Motionfork("dataset stats --protocol nope --data " + dir.path().string());
  CHECK(r.status == 2);
  CHECK(r.output.find("bandai") != std::string::npos);
}
