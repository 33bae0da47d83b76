#include "io/videopose3d.h"

#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/file_util.h"
#include "io/npy.h"
#include "test_support.h"

namespace motionfork {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs a shell command with its output sent to log; returns its exit code (-1 if it did not exit).
int Run(const std::string& command, const std::string& log) {
  const int status = std::system((command + " >" + ShellQuote(log) + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A Python 3 interpreter that has numpy, or "" (the tests then skip). MOTIONFORK_PYTHON wins;
// Debian's /usr/bin/python3 is tried after the one on PATH (which may be a pyenv without numpy).
std::string PythonWithNumpy() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("MOTIONFORK_PYTHON")) candidates.emplace_back(env);
  candidates.emplace_back("python3");
  candidates.emplace_back("/usr/bin/python3");
  for (const std::string& c : candidates) {
    const std::string cmd = (c == "python3" ? c : ShellQuote(c)) + " -c 'import numpy'";
    if (std::system((cmd + " >/dev/null 2>&1").c_str()) == 0)
      return c == "python3" ? c : ShellQuote(c);
  }
  return "";
}

std::string Tool() {
  return ShellQuote(std::string(MOTIONFORK_SOURCE_DIR) + "/tools/videopose3d_to_motionfork.py");
}

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string ManifestError(const TempDir& dir, const std::string& text) {
  WriteText(dir.file("manifest.tsv"), text);
  try {
    ReadVideoPose3dManifest(dir.path().string());
  } catch (const FormatError& e) {
    return e.what();
  }
  FAIL("expected a FormatError for:\n" << text);
  return "";
}

const char kHeader[] = "subject\taction\tframes\tjoints\tfps\tfile\n";

TEST_CASE("videopose3d: manifest rows are parsed and paths resolved against the folder",
          "[io][videopose3d]") {
  TempDir dir;
  WriteText(dir.file("manifest.tsv"),
            std::string(kHeader) +
                "S1\tWalking 1\t1383\t32\t50\tS1/Walking 1.npy\r\n"
                "Train/S3\tJog 1 chunk0\t300\t15\t59.94\tTrain/S3/Jog 1 chunk0.npy\n"
                "\n"
                "S9\tEating\t10\t32\t50\t/abs/S9/Eating.npy\n");
  const auto takes = ReadVideoPose3dManifest(dir.path().string());
  REQUIRE(takes.size() == 3);
  CHECK(takes[0].subject == "S1");
  CHECK(takes[0].action == "Walking 1");
  CHECK(takes[0].frames == 1383);
  CHECK(takes[0].joints == 32);
  CHECK(takes[0].fps == 50.0);
  CHECK(fs::path(takes[0].path) == dir.path() / "S1" / "Walking 1.npy");
  CHECK(takes[1].subject == "Train/S3");
  CHECK(takes[1].action == "Jog 1 chunk0");
  CHECK(takes[1].fps == 59.94);
  CHECK(fs::path(takes[1].path) == dir.path() / "Train/S3/Jog 1 chunk0.npy");
  CHECK(takes[2].path == "/abs/S9/Eating.npy");

  SECTION("columns are found by name") {
    WriteText(dir.file("manifest.tsv"),
              "file\tfps\tjoints\tframes\taction\tsubject\tnote\n"
              "a.npy\t60\t15\t7\tBox 1 chunk0\tValidate/S2\textra\n");
    const auto t = ReadVideoPose3dManifest(dir.path().string());
    REQUIRE(t.size() == 1);
    CHECK(t[0].subject == "Validate/S2");
    CHECK(t[0].frames == 7);
    CHECK(t[0].joints == 15);
  }
}

TEST_CASE("videopose3d: malformed manifests name the line", "[io][videopose3d]") {
  TempDir dir;
  const std::string h = kHeader;
  const std::string ok = "S1\tWalking\t100\t32\t50\tS1/Walking.npy\n";
  REQUIRE_THAT(ManifestError(dir, ""), Catch::Contains("empty manifest"));
  REQUIRE_THAT(ManifestError(dir, h), Catch::Contains("no takes"));
  REQUIRE_THAT(ManifestError(dir, "subject\taction\tframes\tfps\tfile\n" + ok),
               Catch::Contains("line 1") && Catch::Contains("no column 'joints'"));
  REQUIRE_THAT(ManifestError(dir, h + ok + "S5\tWalking\t100\t32\t50\n"),
               Catch::Contains("manifest.tsv:line 3") && Catch::Contains("expected 6") &&
                   Catch::Contains("found 5"));
  REQUIRE_THAT(ManifestError(dir, h + "S5\tWalking\tmany\t32\t50\tx.npy\n"),
               Catch::Contains("line 2") && Catch::Contains("frames") && Catch::Contains("'many'"));
  REQUIRE_THAT(ManifestError(dir, h + "S5\tWalking\t100\t0\t50\tx.npy\n"),
               Catch::Contains("joints") && Catch::Contains("'0'"));
  REQUIRE_THAT(ManifestError(dir, h + "S5\tWalking\t100\t32\t-50\tx.npy\n"),
               Catch::Contains("fps") && Catch::Contains("'-50'"));
  REQUIRE_THAT(ManifestError(dir, h + "S5\tWalking\t100\t32\t50\t\n"),
               Catch::Contains("file name"));
  REQUIRE_THAT(ManifestError(dir, h + "\tWalking\t100\t32\t50\tx.npy\n"),
               Catch::Contains("non-empty subject"));
  REQUIRE_THAT(ManifestError(dir, h + ok + "\n" + ok),
               Catch::Contains("line 4") && Catch::Contains("duplicate take"));

  TempDir empty;
  REQUIRE_THROWS_WITH(
      ReadVideoPose3dManifest(empty.path().string()),
      Catch::Contains("no manifest") && Catch::Contains("videopose3d_to_motionfork.py"));
}

// Converts a synthetic npz made by the tool; returns the takes, or fails the test.
std::vector<VideoPose3dTake> MakeAndConvert(const std::string& python, const TempDir& dir,
                                            const std::string& layout, int seed,
                                            const std::string& out) {
  const std::string npz = dir.file(layout + ".npz");
  REQUIRE(Run(python + " " + Tool() + " --make-synthetic " + ShellQuote(npz) + " --layout " +
                  layout + " --seed " + std::to_string(seed),
              dir.file("make.log")) == 0);
  REQUIRE(fs::file_size(npz) < 2u * 1024 * 1024);
  INFO(ReadFileBytes(dir.file("make.log")));
  const int rc =
      Run(python + " " + Tool() + " " + ShellQuote(npz) + " " + ShellQuote(dir.file(out)),
          dir.file("convert.log"));
  INFO(ReadFileBytes(dir.file("convert.log")));
  REQUIRE(rc == 0);
  return ReadVideoPose3dManifest(dir.file(out));
}

void CheckFilesMatchManifest(const std::vector<VideoPose3dTake>& takes) {
  for (const auto& t : takes) {
    INFO(t.subject << " / " << t.action);
    const NpyArray a = ReadNpy(t.path);
    REQUIRE(a.shape == std::vector<int64_t>{t.frames, t.joints, 3});
    const Motion m = ReadNpyMotion(t.path, nullptr, t.fps);
    REQUIRE(m.num_frames() == t.frames);
  }
}

TEST_CASE("videopose3d: synthetic Human3.6M export converts to the manifest layout",
          "[io][videopose3d][python]") {
  const std::string python = PythonWithNumpy();
  if (python.empty()) {
    std::cout << "SKIPPED: python3 with numpy not available" << std::endl;
    return;
  }
  TempDir dir;
  const auto takes = MakeAndConvert(python, dir, "h36m", 5, "out");
  REQUIRE(takes.size() == 21);
  std::map<std::string, std::set<std::string>> actions;
  for (const auto& t : takes) {
    actions[t.subject].insert(t.action);
    CHECK(t.joints == 32);
    CHECK(t.fps == 50.0);
    CHECK(t.frames >= 100);
    CHECK(t.frames < 260);
    CHECK(fs::path(t.path) == fs::path(dir.file("out")) / t.subject / (t.action + ".npy"));
  }
  const std::set<std::string> expected_actions = {"Directions", "Walking", "Walking 1"};
  REQUIRE(actions.size() == 7);
  for (const char* s : {"S1", "S5", "S6", "S7", "S8", "S9", "S11"}) {
    INFO(s);
    REQUIRE(actions.count(s) == 1);
    CHECK(actions[s] == expected_actions);
  }
  CheckFilesMatchManifest(takes);

  SECTION("lengths are deterministic for a seed") {
    const std::string first = ReadFileBytes(dir.file("out/manifest.tsv"));
    MakeAndConvert(python, dir, "h36m", 5, "again");
    REQUIRE(ReadFileBytes(dir.file("again/manifest.tsv")) == first);
    MakeAndConvert(python, dir, "h36m", 6, "other");
    REQUIRE(ReadFileBytes(dir.file("other/manifest.tsv")) != first);
  }
}

TEST_CASE("videopose3d: synthetic HumanEva-I export keeps nested subjects and chunked actions",
          "[io][videopose3d][python]") {
  const std::string python = PythonWithNumpy();
  if (python.empty()) {
    std::cout << "SKIPPED: python3 with numpy not available" << std::endl;
    return;
  }
  TempDir dir;
  const auto takes = MakeAndConvert(python, dir, "humaneva", 1, "out");
  std::set<std::string> subjects;
  std::set<std::pair<std::string, std::string>> keys;
  for (const auto& t : takes) {
    subjects.insert(t.subject);
    keys.emplace(t.subject, t.action);
    CHECK(t.joints == 15);
    CHECK(t.fps == 60.0);
  }
  REQUIRE(subjects == std::set<std::string>{"Train/S1", "Train/S2", "Train/S3", "Validate/S1",
                                            "Validate/S2", "Validate/S3"});
  // The three takes the protocol drops are there to be dropped.
  CHECK(keys.count({"Train/S3", "Walking 1 chunk0"}) == 1);
  CHECK(keys.count({"Train/S3", "Walking 1 chunk2"}) == 1);
  CHECK(keys.count({"Validate/S3", "Walking 1 chunk4"}) == 1);
  CHECK(keys.count({"Validate/S1", "Jog 1 chunk0"}) == 1);
  CHECK(fs::is_regular_file(dir.file("out/Train/S3/Walking 1 chunk0.npy")));
  // Some takes are shorter than a HumanEva window (15 + 60 frames), some longer.
  int short_takes = 0;
  for (const auto& t : takes) short_takes += t.frames < 75;
  CHECK(short_takes > 0);
  CHECK(short_takes < static_cast<int>(takes.size()));
  CheckFilesMatchManifest(takes);
}

TEST_CASE("videopose3d: the converter rejects bad input with exit code 2 and writes nothing",
          "[io][videopose3d][python]") {
  const std::string python = PythonWithNumpy();
  if (python.empty()) {
    std::cout << "SKIPPED: python3 with numpy not available" << std::endl;
    return;
  }
  TempDir dir;
  const std::string log = dir.file("log.txt");
  auto convert = [&](const std::string& npz, const std::string& out,
                     const std::string& extra = "") {
    return Run(python + " " + Tool() + " " + ShellQuote(dir.file(npz)) + " " +
                   ShellQuote(dir.file(out)) + extra,
               log);
  };
  auto make_npz = [&](const std::string& name, const std::string& expr) {
    const std::string script =
        "import numpy as np; np.savez(" + ShellQuote(dir.file(name)) + ", " + expr + ")";
    REQUIRE(Run(python + " -c " + ShellQuote(script), log) == 0);
  };

  REQUIRE(convert("missing.npz", "o1") == 2);
  CHECK_THAT(ReadFileBytes(log), Catch::Contains("no such file"));
  CHECK_FALSE(fs::exists(dir.file("o1/manifest.tsv")));

  make_npz("wrong_key.npz", "poses=np.zeros(3)");
  REQUIRE(convert("wrong_key.npz", "o2") == 2);
  CHECK_THAT(ReadFileBytes(log), Catch::Contains("positions_3d") && Catch::Contains("poses"));
  CHECK_FALSE(fs::exists(dir.file("o2/manifest.tsv")));

  make_npz("bad_shape.npz", "positions_3d={'S1': {'Walking': np.zeros((10, 32), np.float32)}}");
  REQUIRE(convert("bad_shape.npz", "o3") == 2);
  CHECK_THAT(ReadFileBytes(log), Catch::Contains("[T, J, 3]") && Catch::Contains("Walking"));

  make_npz("nan.npz",
           "positions_3d={'S1': {'Walking': np.where(np.arange(96).reshape(1, 32, 3) == 40, "
           "np.nan, 0).astype(np.float32)}}");
  REQUIRE(convert("nan.npz", "o4") == 2);
  CHECK_THAT(ReadFileBytes(log), Catch::Contains("frame 0, joint 13, coordinate y"));
  CHECK_FALSE(fs::exists(dir.file("o4")));

  make_npz("j17.npz", "positions_3d={'S1': {'Walking': np.ones((5, 17, 3), np.float32)}}");
  REQUIRE(convert("j17.npz", "o5") == 2);
  CHECK_THAT(ReadFileBytes(log), Catch::Contains("--fps"));
  REQUIRE(convert("j17.npz", "o5", " --fps 30") == 0);
  const auto takes = ReadVideoPose3dManifest(dir.file("o5"));
  REQUIRE(takes.size() == 1);
  CHECK(takes[0].fps == 30.0);
  CHECK(takes[0].joints == 17);

  REQUIRE(Run(python + " " + Tool() + " --help", log) == 0);
  CHECK_THAT(ReadFileBytes(log), Catch::Contains("--make-synthetic"));
  REQUIRE(Run(python + " " + Tool(), log) == 2);
}

TEST_CASE("videopose3d: our .npy writer matches numpy's np.save byte for byte",
          "[io][videopose3d][npy][python]") {
  const std::string python = PythonWithNumpy();
  if (python.empty()) {
    std::cout << "SKIPPED: python3 with numpy not available" << std::endl;
    return;
  }
  TempDir dir;
  for (const std::vector<int64_t>& shape :
       std::vector<std::vector<int64_t>>{{3, 17, 3}, {5}, {}, {1234567, 0, 3}, {2, 2, 2, 2}}) {
    NpyArray a;
    a.shape = shape;
    size_t n = 1;
    for (int64_t d : shape) n *= static_cast<size_t>(d);
    for (size_t i = 0; i < n; ++i) a.data.push_back(0.37f * static_cast<float>(i) - 1.0f);
    WriteNpy(dir.file("ours.npy"), a);
    const std::string script =
        "import numpy as np, sys; np.save(sys.argv[2], np.load(sys.argv[1]))";
    REQUIRE(Run(python + " -c " + ShellQuote(script) + " " + ShellQuote(dir.file("ours.npy")) +
                    " " + ShellQuote(dir.file("theirs.npy")),
                dir.file("log.txt")) == 0);
    INFO("shape of " << shape.size() << " dims");
    CHECK(ReadFileBytes(dir.file("ours.npy")) == ReadFileBytes(dir.file("theirs.npy")));
  }
}

}  // namespace
}  // namespace motionfork
