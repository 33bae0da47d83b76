#include "io/csv.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/file_util.h"
#include "io/npy.h"
#include "test_support.h"

namespace motionfork {
namespace {

using testing::MakeHumanoid;
using testing::MakeWalkingMotion;
using testing::TempDir;

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A two-joint skeleton for hand-written files.
std::shared_ptr<const Skeleton> TwoJoints() {
  return std::make_shared<const Skeleton>(Skeleton::FromParents("two", {"A", "B"}, {-1, 0}));
}

class CsvFixture {
 public:
  // Reads text as a CSV file with the given skeleton and fallback fps.
  Motion Read(const std::string& text, std::shared_ptr<const Skeleton> skeleton = TwoJoints(),
              double fps = 25.0) {
    WriteText(dir_.file("in.csv"), text);
    return ReadCsvMotion(dir_.file("in.csv"), std::move(skeleton), fps);
  }
  // The FormatError message of reading text; fails the test when reading succeeds.
  std::string Error(const std::string& text, std::shared_ptr<const Skeleton> skeleton = TwoJoints(),
                    double fps = 25.0) {
    try {
      Read(text, std::move(skeleton), fps);
    } catch (const FormatError& e) {
      return e.what();
    }
    FAIL("expected a FormatError for:\n" << text);
    return "";
  }
  TempDir dir_;
};

TEST_CASE("csv: motion round trip is exact", "[io][csv]") {
  TempDir dir;
  const Motion motion = MakeWalkingMotion(25);
  const std::string path = dir.file("walk.csv");
  WriteCsvMotion(path, motion);

  const std::string text = ReadFileBytes(path);
  std::istringstream lines(text);
  std::string first, second;
  std::getline(lines, first);
  std::getline(lines, second);
  REQUIRE(first == "# motionfork positions; fps=30; unit=m; skeleton=test_humanoid");
  REQUIRE(second.rfind("Hips.x,Hips.y,Hips.z,UpperLeg_R.x,", 0) == 0);

  const Motion back = ReadCsvMotion(path, MakeHumanoid(), /*fps=*/0.0);
  REQUIRE(back.fps() == 30.0);
  REQUIRE(back.num_frames() == 25);
  REQUIRE(back.skeleton().SameStructure(motion.skeleton()));
  for (size_t i = 0; i < motion.positions().size(); ++i) {
    REQUIRE(std::fabs(back.positions()[i] - motion.positions()[i]) <= 1e-5f);
  }
  REQUIRE(back.positions() == motion.positions());  // shortest round-trip digits: exact

  SECTION("awkward float32 values survive too") {
    std::vector<float> p = {1e-45f, -0.0f, 3.4028235e38f, 0.1f, 1.0f / 3.0f, -123456.79f};
    const Motion odd(TwoJoints(), 120.5, p);
    WriteCsvMotion(dir.file("odd.csv"), odd);
    const Motion odd_back = ReadCsvMotion(dir.file("odd.csv"), TwoJoints(), 1.0);
    REQUIRE(odd_back.positions() == p);
    REQUIRE(std::signbit(odd_back.positions()[1]));
    REQUIRE(odd_back.fps() == 120.5);
  }
  SECTION("without a skeleton the header names the joints") {
    const Motion named = ReadCsvMotion(path, nullptr, 0.0);
    REQUIRE(named.num_joints() == 17);
    REQUIRE(named.skeleton().joint_names() == motion.skeleton().joint_names());
    REQUIRE(named.skeleton().name() == "test_humanoid");
    REQUIRE(named.positions() == motion.positions());
  }
  SECTION("an anonymous motion stays anonymous") {
    const std::string npy = dir.file("anon.npy");
    WriteNpyMotion(npy, motion);
    const Motion anon = ReadNpyMotion(npy, nullptr, 30.0);
    WriteCsvMotion(dir.file("anon.csv"), anon);
    const Motion anon_back = ReadCsvMotion(dir.file("anon.csv"), nullptr, 0.0);
    REQUIRE(anon_back.skeleton().is_anonymous());
    REQUIRE(anon_back.positions() == motion.positions());
  }
}

TEST_CASE("csv: columns map to the skeleton by name in any order", "[io][csv]") {
  CsvFixture f;
  const Motion m = f.Read(
      "B.z,A.x,B.x,A.z,A.y,B.y\n"
      "6,1,4,3,2,5\n"
      "60,10,40,30,20,50\n");
  REQUIRE(m.num_frames() == 2);
  REQUIRE(m.positions() == std::vector<float>{1, 2, 3, 4, 5, 6, 10, 20, 30, 40, 50, 60});
  REQUIRE(m.fps() == 25.0);  // no fps comment: the fallback

  SECTION("with the humanoid, reversed column order") {
    const Motion motion = MakeWalkingMotion(3);
    const Skeleton& s = motion.skeleton();
    std::string text = "# fps=30\n";
    for (int j = s.num_joints() - 1; j >= 0; --j) {
      text += s.joint_name(j) + ".z," + s.joint_name(j) + ".y," + s.joint_name(j) + ".x";
      text += j ? "," : "\n";
    }
    char buf[64];
    for (int t = 0; t < 3; ++t) {
      for (int j = s.num_joints() - 1; j >= 0; --j) {
        for (int a = 2; a >= 0; --a) {
          std::snprintf(buf, sizeof(buf), "%.9g", motion.at(t, j)[a]);
          text += buf;
          text += (j == 0 && a == 0) ? "\n" : ",";
        }
      }
    }
    const Motion back = f.Read(text, MakeHumanoid(), 0.0);
    REQUIRE(back.positions() == motion.positions());  // %.9g round-trips float32 exactly
  }
}

TEST_CASE("csv: comments, line endings and number forms", "[io][csv]") {
  CsvFixture f;
  SECTION("CRLF, BOM, blank lines, spaces, signs and exponents") {
    const Motion m = f.Read(
        "\xEF\xBB\xBF# exported by hand\r\n"
        "# fps=50 unit=m\r\n"
        "\r\n"
        " A.x , A.y , A.z , B.x , B.y , B.z \r\n"
        "+1, -2 , 3e0,4.5E-1, .5, 6.\r\n"
        "# a comment between rows\r\n"
        "\r\n"
        "0,0,0,0,0,1e-50\r\n"
        "\r\n");
    REQUIRE(m.fps() == 50.0);
    REQUIRE(m.num_frames() == 2);
    REQUIRE(m.positions() == std::vector<float>{1, -2, 3, 0.45f, 0.5f, 6, 0, 0, 0, 0, 0, 0});
  }
  SECTION("fps in the file wins over the fallback; units convert to metres") {
    const Motion m = f.Read(
        "# motionfork positions; fps=120; unit=cm; "
        "skeleton=two\nA.x,A.y,A.z,B.x,B.y,B.z\n100,200,-50,0,1,2\n",
        TwoJoints(), 30.0);
    REQUIRE(m.fps() == 120.0);
    REQUIRE(m.positions()[0] == Approx(1.0f));
    REQUIRE(m.positions()[1] == Approx(2.0f));
    REQUIRE(m.positions()[2] == Approx(-0.5f));
    const Motion mm = f.Read("# unit=mm\nA.x,A.y,A.z,B.x,B.y,B.z\n1000,0,0,0,0,0\n");
    REQUIRE(mm.positions()[0] == Approx(1.0f));
  }
  SECTION("last line without a newline") {
    REQUIRE(f.Read("A.x,A.y,A.z,B.x,B.y,B.z\n1,2,3,4,5,6").num_frames() == 1);
  }
}

TEST_CASE("csv: errors name the file, line and column", "[io][csv]") {
  CsvFixture f;
  const std::string header = "A.x,A.y,A.z,B.x,B.y,B.z\n";

  SECTION("empty and header-only files") {
    REQUIRE_THAT(f.Error(""), Catch::Contains("in.csv") && Catch::Contains("empty file"));
    REQUIRE_THAT(f.Error("# fps=30\n\n"), Catch::Contains("no header"));
    REQUIRE_THAT(f.Error(header), Catch::Contains("no data rows") && Catch::Contains("line 1") &&
                                      Catch::Contains("at least one frame"));
    REQUIRE_THAT(f.Error("# c\n" + header + "\n\n# end\n"), Catch::Contains("no data rows"));
  }
  SECTION("non-numbers, NaN, Inf, out of range") {
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,6\n1,2,abc,4,5,6\n"),
                 Catch::Contains("line 3, column 3 (A.z)") && Catch::Contains("'abc'"));
    REQUIRE_THAT(f.Error(header + "1,2,3,4,,6\n"),
                 Catch::Contains("line 2, column 5 (B.y)") && Catch::Contains("expected a number"));
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,1e\n"), Catch::Contains("column 6"));
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,0x10\n"), Catch::Contains("column 6"));
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,1;5\n"), Catch::Contains("column 6"));
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,+-1\n"), Catch::Contains("column 6"));
    REQUIRE_THAT(f.Error(header + "1,nan,3,4,5,6\n"),
                 Catch::Contains("line 2, column 2 (A.y)") && Catch::Contains("finite"));
    REQUIRE_THAT(f.Error(header + "1,2,3,-inf,5,6\n"),
                 Catch::Contains("line 2, column 4 (B.x)") && Catch::Contains("finite"));
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,1e39\n"), Catch::Contains("float32 range"));
  }
  SECTION("wrong column counts") {
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,6\n1,2,3,4,5\n"),
                 Catch::Contains("line 3") && Catch::Contains("expected 6 columns") &&
                     Catch::Contains("found 5"));
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,6,\n"), Catch::Contains("found 7"));
  }
  SECTION("header problems") {
    REQUIRE_THAT(f.Error("frame,A.x,A.y,A.z,B.x,B.y,B.z\n0,1,2,3,4,5,6\n"),
                 Catch::Contains("line 1, column 1") && Catch::Contains("'frame'"));
    REQUIRE_THAT(f.Error("A.x,A.y,A.z,B.x,B.y,B.w\n1,2,3,4,5,6\n"),
                 Catch::Contains("column 6") && Catch::Contains("'B.w'"));
    REQUIRE_THAT(f.Error("A.x,A.y,A.z,C.x,C.y,C.z,D.x\n1,2,3,4,5,6,7\n"),
                 Catch::Contains("line 1") && Catch::Contains("unknown joint names C, D") &&
                     Catch::Contains("has joints A, B"));
    REQUIRE_THAT(f.Error("A.x,A.y,A.z,B.x,B.z\n1,2,3,4,5\n"),
                 Catch::Contains("missing columns for joint B (y)"));
    REQUIRE_THAT(f.Error("A.x,A.y,A.z\n1,2,3\n"),
                 Catch::Contains("missing columns for joint B (x/y/z)"));
    REQUIRE_THAT(f.Error("A.x,A.y,A.z,B.x,B.y,B.z,A.y\n1,2,3,4,5,6,7\n"),
                 Catch::Contains("column 7") && Catch::Contains("duplicate column 'A.y'") &&
                     Catch::Contains("column 2"));
    REQUIRE_THAT(f.Error("A.x,A.y,A.z,B.x,B.y\n1,2,3,4,5\n", nullptr),
                 Catch::Contains("missing columns for joint B (z)"));
  }
  SECTION("comments and frame rate") {
    REQUIRE_THAT(f.Error("# fps=-3\n" + header + "1,2,3,4,5,6\n"),
                 Catch::Contains("line 1") && Catch::Contains("fps="));
    REQUIRE_THAT(f.Error("# fps=thirty\n" + header + "1,2,3,4,5,6\n"), Catch::Contains("'thirty'"));
    REQUIRE_THAT(f.Error("#\n# unit=inch\n" + header + "1,2,3,4,5,6\n"),
                 Catch::Contains("line 2") && Catch::Contains("unit=m"));
    REQUIRE_THAT(f.Error(header + "1,2,3,4,5,6\n", TwoJoints(), 0.0), Catch::Contains("fps="));
  }
  SECTION("a missing file") {
    REQUIRE_THROWS_AS(ReadCsvMotion(f.dir_.file("nope.csv"), TwoJoints(), 30.0), FormatError);
  }
}

TEST_CASE("csv: writer refuses unwritable names and is all-or-nothing", "[io][csv]") {
  TempDir dir;
  const Motion bad_names(
      std::make_shared<const Skeleton>(Skeleton::FromParents("s", {"A", "B,C"}, {-1, 0})), 30.0,
      std::vector<float>(6, 0.0f));
  REQUIRE_THROWS_AS(WriteCsvMotion(dir.file("x.csv"), bad_names), std::invalid_argument);
  REQUIRE_FALSE(std::filesystem::exists(dir.file("x.csv")));

  std::ofstream(dir.file("plain_file")) << "x";
  const std::string path = dir.file("plain_file") + "/out.csv";
  REQUIRE_THROWS_AS(WriteCsvMotion(path, MakeWalkingMotion(2)), FormatError);
  REQUIRE_FALSE(std::filesystem::exists(path));

  // Skeleton names with separators are made safe for the comment line.
  const Motion spaced(
      std::make_shared<const Skeleton>(Skeleton::FromParents("my skel;v2", {"A", "B"}, {-1, 0})),
      30.0, std::vector<float>(6, 0.0f));
  WriteCsvMotion(dir.file("s.csv"), spaced);
  REQUIRE(ReadCsvMotion(dir.file("s.csv"), nullptr, 0).skeleton().name() == "my_skel_v2");
}

}  // namespace
}  // namespace motionfork
