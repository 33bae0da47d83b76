// Hostile and damaged inputs and outputs end to end (issue 23): the command never hangs, never
// crashes, never overwrites an input and stays within 1 GiB; each refusal exits with status 2 and
// a message naming the file and what was wrong, and leaves nothing behind.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "api/tiny_bundle.h"
#include "io/csv.h"
#include "io/file_util.h"
#include "io/motion_file.h"
#include "io/prediction_file.h"
#include "run_motionfork.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;
using testing::Run;

namespace {

namespace fs = std::filesystem;

// `motionfork --cache-dir none ARGS` with a 1 GiB address-space limit and a 60 s timeout (a hang
// fails the test with status 124 instead of blocking it).
Run Limited(const std::string& args) {
  return testing::RunShell(std::string("ulimit -v 1048576; timeout 60 ") + MOTIONFORK_BINARY +
                           " --cache-dir none " + args + " 2>&1");
}

struct Fixture {
  testing::TempDir dir;
  std::string bundle = dir.file("bundle"), history = dir.file("h.npy");
  Fixture() {
    testing::WriteTinyBundle(bundle, MOTIONFORK_CONFIG_DIR);
    WriteMotionFile(history, testing::TinyBundleHistory(12));
  }
  std::string Predict(const std::string& history_file, const std::string& out,
                      const std::string& k = "3") const {
    return "predict " + history_file + " --model " + bundle + " -k " + k + " -o " + out;
  }
};

}  // namespace

TEST_CASE("a FIFO or a symbolic link loop is refused at once, saying what it is") {
  Fixture f;
  const std::string fifo = f.dir.file("f.bvh");
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  Run r = Limited("info " + fifo);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("f.bvh") && Contains("FIFO"));
  r = Limited("predict --history " + fifo + " --model " + f.bundle + " -o " + f.dir.file("p"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("f.bvh") && Contains("FIFO"));
  fs::create_symlink(f.dir.file("b.bvh"), f.dir.file("a.bvh"));
  fs::create_symlink(f.dir.file("a.bvh"), f.dir.file("b.bvh"));
  r = Limited("info " + f.dir.file("a.bvh"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("a.bvh") && Contains("symbolic link loop"));
  CHECK_FALSE(fs::exists(f.dir.file("p.npy")));
}

TEST_CASE("predict: -k above its limit, -k 0 and seeds outside 0..2^64-1 are refused readably") {
  Fixture f;
  const std::string p = f.dir.file("p");
  Run r = Limited(f.Predict(f.history, p, "1000000"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("expected 1..10000 futures per history (k), got 1000000"));
  r = Limited(f.Predict(f.history, p, "0"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("expected a number > 0, found '0'"));
  CHECK(r.output.size() < 300);  // no 309-digit bound
  for (const std::string seed : {"-1", "1e23", "18446744073709551616"}) {
    r = Limited(f.Predict(f.history, p) + " --seed " + seed);
    CHECK(r.status == 2);
    CHECK_THAT(r.output, Contains("expected an integer 0..18446744073709551615, found '" + seed));
  }
  r = Limited(f.Predict(f.history, p) + " --seed 18446744073709551615");
  CHECK(r.status == 0);
  CHECK(ReadPrediction(f.dir.file("p.json")).seed == 18446744073709551615ull);
}

TEST_CASE("size claims and huge files fail in 1 GiB with the limit named") {
  testing::TempDir dir;
  // 50 MB of blank lines.
  std::ofstream(dir.file("blank.csv"), std::ios::binary) << std::string(50u << 20, '\n');
  Run r = Limited("info " + dir.file("blank.csv"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("blank.csv") && Contains("no header line"));
  // A 3 GB sparse file.
  std::ofstream(dir.file("big.npy")).put('\x93');
  fs::resize_file(dir.file("big.npy"), uint64_t{3} << 30);
  r = Limited("info " + dir.file("big.npy"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("big.npy") && Contains("MOTIONFORK_MAX_INPUT_MB"));
  // 81 bytes claiming 89 million frames.
  std::ofstream(dir.file("claim.bvh"))
      << "HIERARCHY\nROOT R\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 89000000\n"
         "Frame Time: 0.1\n";
  r = Limited("info " + dir.file("claim.bvh"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("claim.bvh:line") && Contains("89000000"));
  CHECK_THAT(r.output, !Contains("bad_alloc"));
}

TEST_CASE("an output that names an input, or no file, is refused and the input stays") {
  Fixture f;
  const std::string before = ReadFileBytes(f.history);
  const std::string h_base = f.dir.file("h");
  for (const std::string& out : {f.history, h_base, h_base + ".json"}) {
    const Run r = Limited(f.Predict(f.history, out));
    CHECK(r.status == 2);
    CHECK_THAT(r.output, Contains("would be overwritten") && Contains("h.npy"));
  }
  CHECK(ReadFileBytes(f.history) == before);
  CHECK_FALSE(fs::exists(f.dir.file("h.json")));
  Run r = Limited("convert " + f.history + " " + f.dir.file("sub/../h.npy"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("would be overwritten"));
  r = Limited("info " + f.history + " --json " + f.history);
  CHECK(r.status == 2);
  CHECK(ReadFileBytes(f.history) == before);
  r = Limited(f.Predict(f.history, "''"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("output path is empty"));
  r = Limited(f.Predict(f.history, f.dir.file("out/")));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("names a folder"));
  CHECK_FALSE(fs::exists(f.dir.file("out")));
  CHECK(testing::TemporaryLeftovers(f.dir.path()).empty());
}

TEST_CASE("predict writes .npy and .json as one set and cleans leftovers of killed writes") {
  Fixture f;
  const std::string out = f.dir.file("p");
  REQUIRE(Limited(f.Predict(f.history, out)).status == 0);
  // Leftovers of a killed write: a temporary file, and a set folder that never started moving.
  std::ofstream(out + ".npy.tmp4999999") << "half";
  fs::create_directories(f.dir.path() / ".p.npy.tmp4999998" / "new");
  std::ofstream(f.dir.path() / ".p.npy.tmp4999998" / "names") << "p.npy\np.json\n";
  Run r = Limited(f.Predict(f.history, out, "4"));
  REQUIRE(r.status == 0);
  CHECK(ReadPrediction(out + ".json").k == 4);
  CHECK(testing::TemporaryLeftovers(f.dir.path()).empty());

  // The .json cannot be written (a folder of its name): nothing changes, the old .npy stays.
  const std::string q = f.dir.file("q");
  REQUIRE(Limited(f.Predict(f.history, q)).status == 0);
  const std::string old_npy = ReadFileBytes(q + ".npy");
  fs::remove(q + ".json");
  fs::create_directories(q + ".json/inside");
  r = Limited(f.Predict(f.history, q, "5"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("q.json") && Contains("is a folder"));
  CHECK(ReadFileBytes(q + ".npy") == old_npy);
  CHECK(testing::TemporaryLeftovers(f.dir.path()).empty());
}

TEST_CASE("dataset cache: an unwritable folder is a warning, a damaged cache is rebuilt") {
  testing::TempDir dir;
  const std::string data = dir.file("data");
  fs::create_directories(data);
  REQUIRE(testing::Motionfork("synth walk --frames 160 -o " + data + "/walk_a.bvh").status == 0);
  std::ofstream(dir.file("split.tsv")) << "train\twalk_a.bvh\n";
  std::ofstream(dir.file("file")) << "not a folder";
  auto stats = [&](const std::string& cache) {
    return testing::RunShell(std::string(MOTIONFORK_BINARY) + " --quiet --cache-dir " + cache +
                             " dataset stats --protocol bandai --data " + data + " --split " +
                             dir.file("split.tsv") + " 2>&1");
  };
  Run r = stats(dir.file("file") + "/cache");  // cannot be created: under a file
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("warning") && Contains("without a dataset cache"));

  const std::string cache = dir.file("cache");
  REQUIRE(stats(cache).status == 0);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(cache)) files.push_back(e.path());
  REQUIRE(files.size() == 1);
  const std::string good = ReadFileBytes(files[0].string());
  std::string damaged = good;
  for (int i = 20; i < 24; ++i) damaged[i] = '\xff';  // the skeleton count: 4 billion
  WriteFileAtomically(files[0].string(), damaged);
  r = stats(cache);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("warning") && Contains("rebuilding the cache"));
  CHECK_THAT(r.output, !Contains("bad_alloc"));
  CHECK(ReadFileBytes(files[0].string()) == good);
  r = stats(cache);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, !Contains("warning"));
}

TEST_CASE("messages: a JSON type error names the file, --json is valid for any file name") {
  Fixture f;
  const std::string p = f.dir.file("p");
  REQUIRE(Limited(f.Predict(f.history, p)).status == 0);
  nlohmann::json j = nlohmann::json::parse(ReadFileBytes(p + ".json"));
  j["left_right"] = {{"a", "b"}};
  WriteFileAtomically(p + ".json", j.dump());
  Run r = Limited("render " + p + ".json -o " + f.dir.file("p.svg"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("p.json") && Contains("unexpected content"));
  CHECK_THAT(r.output, !Contains("[json.exception"));

  for (const std::string name : {"a\nb.csv", "x\xff.csv"}) {
    const std::string path = f.dir.file(name);
    WriteCsvMotion(path, testing::TinyBundleHistory(8));
    r = testing::RunShell(std::string(MOTIONFORK_BINARY) + " --cache-dir none info '" + path +
                          "' --json -");
    REQUIRE(r.status == 0);
    CHECK_NOTHROW(nlohmann::json::parse(r.output));
  }
}
