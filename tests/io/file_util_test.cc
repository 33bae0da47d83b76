// Reading only regular files (never waiting on a FIFO), writing one file or a set of files
// all-or-nothing, and output paths that would overwrite an input.
#include "io/file_util.h"

#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/error.h"
#include "test_support.h"

namespace motionfork {
namespace {

namespace fs = std::filesystem;
using Catch::Contains;

TEST_CASE("file_util: a FIFO, a folder, a symbolic link loop are refused with what they are") {
  testing::TempDir dir;
  const std::string fifo = dir.file("f.bvh");
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THROWS_WITH(ReadFileBytes(fifo), Contains("FIFO") && Contains("f.bvh"));
  CHECK_THAT(InputFileProblem(fifo), Contains("FIFO"));
  CHECK_THROWS_WITH(ReadFileBytes(dir.path().string()), Contains("a folder"));
  fs::create_symlink(dir.file("b.bvh"), dir.file("a.bvh"));
  fs::create_symlink(dir.file("a.bvh"), dir.file("b.bvh"));
  CHECK_THROWS_WITH(ReadFileBytes(dir.file("a.bvh")), Contains("symbolic link loop"));
  CHECK_THAT(InputFileProblem(dir.file("a.bvh")), Contains("symbolic link loop"));
  fs::create_symlink(dir.file("gone.bvh"), dir.file("dangling.bvh"));
  CHECK_THAT(InputFileProblem(dir.file("dangling.bvh")), Contains("symbolic link to a file"));
  CHECK_THAT(InputFileProblem(dir.file("none.bvh")), Contains("does not exist"));
  WriteFileAtomically(dir.file("ok.txt"), "hello");
  CHECK(InputFileProblem(dir.file("ok.txt")).empty());
  CHECK(ReadFileBytes(dir.file("ok.txt")) == "hello");
}

TEST_CASE("file_util: files above the size limit are refused before they are read") {
  testing::TempDir dir;
  const std::string big = dir.file("big.csv");
  std::ofstream(big).put('a');
  fs::resize_file(big, (uint64_t{3} << 30));  // sparse: no disk used
  CHECK_THROWS_WITH(ReadFileBytes(big),
                    Contains("limit on input files") && Contains("MOTIONFORK_MAX_INPUT_MB"));
  // The head check sees the first bytes only.
  const std::string text = dir.file("t.csv");
  WriteFileAtomically(text, std::string("a,b\n\0\0", 6));
  CHECK_THROWS_WITH(ReadFileBytes(text, RequireTextHead(text, "a CSV text file")),
                    Contains("t.csv:byte 4") && Contains("binary data"));
}

TEST_CASE("file_util: a failed atomic write names the reason and leaves nothing behind") {
  testing::TempDir dir;
  // The target is a folder that is not empty: the rename fails.
  fs::create_directories(dir.path() / "out.json" / "inside");
  try {
    WriteFileAtomically(dir.file("out.json"), "{}");
    FAIL("expected a FormatError");
  } catch (const FormatError& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Contains("out.json") && Contains("into place"));
    CHECK_THAT(what, !Contains("Success"));
  }
  CHECK(testing::TemporaryLeftovers(dir.path()).empty());
  // Leftovers of a killed writer (a pid that cannot be alive) go on the next write.
  std::ofstream(dir.file("a.txt.tmp4999999")) << "half";
  WriteFileAtomically(dir.file("a.txt"), "whole");
  CHECK(testing::TemporaryLeftovers(dir.path()).empty());
  CHECK(ReadFileBytes(dir.file("a.txt")) == "whole");
}

TEST_CASE("file_util: a file set is replaced whole or not at all") {
  testing::TempDir dir;
  const std::string d = dir.path().string();
  WriteFileSet(d, {{"p.npy", "old array"}, {"p.json", "old description"}});
  WriteFileSet(d, {{"p.npy", "new array"}, {"p.json", "new description"}});
  CHECK(ReadFileBytes(dir.file("p.npy")) == "new array");
  CHECK(ReadFileBytes(dir.file("p.json")) == "new description");

  // A folder where the second file goes: refused before anything moves (a folder is never moved
  // aside), the first file stays the old one.
  fs::create_directories(dir.path() / "q.json" / "inside");
  WriteFileAtomically(dir.file("q.npy"), "old q");
  CHECK_THROWS_WITH(WriteFileSet(d, {{"q.npy", "new q"}, {"q.json", "new"}}),
                    Contains("q.json") && Contains("is a folder"));
  CHECK(ReadFileBytes(dir.file("q.npy")) == "old q");
  CHECK(fs::is_directory(dir.path() / "q.json" / "inside"));
  CHECK(testing::TemporaryLeftovers(dir.path()).empty());

  // A writer killed after moving the new p.npy in: the next write's recovery restores the old
  // set first.
  const fs::path temp = dir.path() / ".p.npy.tmp4999999";
  fs::create_directories(temp / "old");
  fs::create_directories(temp / "new");
  std::ofstream(temp / "names") << "p.npy\np.json\n";
  fs::rename(dir.path() / "p.npy", temp / "old" / "p.npy");
  fs::rename(dir.path() / "p.json", temp / "old" / "p.json");
  std::ofstream(dir.path() / "p.npy") << "newest array";
  std::ofstream(temp / "new" / "p.json") << "newest description";
  RecoverFileSets(d);
  CHECK(ReadFileBytes(dir.file("p.npy")) == "new array");
  CHECK(ReadFileBytes(dir.file("p.json")) == "new description");
  CHECK(testing::TemporaryLeftovers(dir.path()).empty());
}

TEST_CASE("file_util: an output that names an input, or no file, is refused") {
  testing::TempDir dir;
  WriteFileAtomically(dir.file("h.npy"), "history");
  const std::string h = dir.file("h.npy");
  CHECK_THROWS_WITH(RequireSeparateOutput(h, {h}), Contains("would be overwritten"));
  // A prediction OUT writes OUT.npy and OUT.json.
  CHECK_THROWS_WITH(RequireSeparateOutput(dir.file("h"), {h}), Contains("h.npy"));
  CHECK_THROWS_WITH(RequireSeparateOutput(dir.file("h.json"), {h}), Contains("h.npy"));
  // The same file by another path: "..", a symbolic link, a hard link.
  fs::create_directories(dir.path() / "sub");
  CHECK_THROWS(RequireSeparateOutput(dir.file("sub/../h.npy"), {h}));
  fs::create_symlink(h, dir.file("link.npy"));
  CHECK_THROWS(RequireSeparateOutput(dir.file("link.npy"), {h}));
  fs::create_hard_link(h, dir.file("hard.csv"));
  CHECK_THROWS(RequireSeparateOutput(dir.file("hard.csv"), {h}));
  CHECK_THROWS_WITH(RequireSeparateOutput("", {h}), Contains("empty"));
  CHECK_THROWS_WITH(RequireSeparateOutput(dir.file("sub/"), {h}), Contains("names a folder"));
  CHECK_NOTHROW(RequireSeparateOutput(dir.file("out"), {h}));
  CHECK_NOTHROW(RequireSeparateOutput(dir.file("h.csv"), {h}));
}

TEST_CASE("file_util: a bundle written over its input folder is refused, by any path") {
  testing::TempDir dir;
  fs::create_directories(dir.path() / "model" / "sub");
  const std::string model = dir.file("model");
  CHECK_THROWS_WITH(RequireSeparateFolder("calibrate", model, model),
                    Contains("calibrate: --out " + model + " is the input bundle"));
  CHECK_THROWS(RequireSeparateFolder("calibrate", dir.file("model/sub/.."), model));
  CHECK_THROWS(RequireSeparateFolder("calibrate", dir.file("model/"), model));
  fs::create_directory_symlink(dir.path() / "model", dir.path() / "link");
  CHECK_THROWS(RequireSeparateFolder("calibrate", dir.file("link"), model));
  CHECK_NOTHROW(RequireSeparateFolder("calibrate", dir.file("out"), model));
  CHECK_NOTHROW(RequireSeparateFolder("calibrate", dir.file("model/sub"), model));
}

}  // namespace
}  // namespace motionfork
