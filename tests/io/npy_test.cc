#include "io/npy.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "test_support.h"

namespace motionfork {
namespace {

using testing::MakeHumanoid;
using testing::MakeWalkingMotion;
using testing::TempDir;

// A .npy file from its parts, as a test wants it: any version, any header text (padded with
// spaces and a newline to a multiple of 64 unless told otherwise), raw data bytes.
std::string NpyBytes(const std::string& dict, const std::string& data, int major = 1,
                     bool pad = true) {
  const size_t len_size = major == 1 ? 2 : 4;
  std::string header = dict;
  if (pad) {
    const size_t used = 8 + len_size + header.size() + 1;
    header.append((64 - used % 64) % 64, ' ');
    header += '\n';
  }
  std::string out = "\x93NUMPY";
  out += static_cast<char>(major);
  out += '\0';
  for (size_t i = 0; i < len_size; ++i) out += static_cast<char>((header.size() >> (8 * i)) & 0xff);
  return out + header + data;
}

template <typename T>
std::string RawBytes(const std::vector<T>& values) {
  std::string out(values.size() * sizeof(T), '\0');
  std::memcpy(out.data(), values.data(), out.size());  // the test machine is little-endian
  return out;
}

std::string F4Dict(const std::string& shape) {
  return "{'descr': '<f4', 'fortran_order': False, 'shape': " + shape + ", }";
}

// The FormatError message of parsing bytes; fails the test when parsing succeeds.
std::string ParseError(const std::string& bytes) {
  try {
    ParseNpy(bytes, "test.npy");
  } catch (const FormatError& e) {
    return e.what();
  }
  FAIL("expected a FormatError");
  return "";
}

TEST_CASE("npy: motion round trip is exact for float32", "[io][npy]") {
  TempDir dir;
  const Motion motion = MakeWalkingMotion(40);
  const std::string path = dir.file("walk.npy");
  WriteNpyMotion(path, motion);
  const Motion back = ReadNpyMotion(path, MakeHumanoid(), 30.0);
  REQUIRE(back.num_frames() == 40);
  REQUIRE(back.num_joints() == 17);
  REQUIRE(back.fps() == 30.0);
  REQUIRE(back.positions() == motion.positions());

  const NpyArray raw = ReadNpy(path);
  REQUIRE(raw.shape == std::vector<int64_t>{40, 17, 3});

  SECTION("without a skeleton an anonymous one is used") {
    const Motion anon = ReadNpyMotion(path, nullptr, 50.0);
    REQUIRE(anon.skeleton().is_anonymous());
    REQUIRE(anon.num_joints() == 17);
    REQUIRE(anon.positions() == motion.positions());
  }
}

TEST_CASE("npy: writer output has numpy's header layout", "[io][npy]") {
  NpyArray a;
  a.shape = {2, 3};
  a.data = {1, 2, 3, 4, 5, 6};
  const std::string bytes = SerializeNpy(a);
  REQUIRE(bytes.substr(0, 8) == std::string("\x93NUMPY\x01\x00", 8));
  const size_t header_len =
      static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
  REQUIRE((10 + header_len) % 64 == 0);
  REQUIRE(bytes.size() == 10 + header_len + 6 * 4);
  const std::string header = bytes.substr(10, header_len);
  REQUIRE(header.back() == '\n');
  // np.save's text, with its room for the first axis to grow to 21 digits.
  REQUIRE(header.rfind(F4Dict("(2, 3)") + std::string(20, ' '), 0) == 0);
  REQUIRE(10 + header_len == 128);
  REQUIRE(header ==
          F4Dict("(2, 3)") + std::string(header_len - F4Dict("(2, 3)").size() - 1, ' ') + "\n");

  const NpyArray back = ParseNpy(bytes, "mem");
  REQUIRE(back.shape == a.shape);
  REQUIRE(back.data == a.data);

  SECTION("1-D and 0-D shapes") {
    NpyArray v;
    v.shape = {4};
    v.data = {0.5f, -1.25f, 3e-7f, 1e30f};
    std::string b = SerializeNpy(v);
    REQUIRE(b.find("'shape': (4,), }") != std::string::npos);
    REQUIRE(ParseNpy(b, "v").data == v.data);
    NpyArray s;
    s.shape = {};
    s.data = {7.0f};
    b = SerializeNpy(s);
    REQUIRE(b.find("'shape': (), }") != std::string::npos);
    REQUIRE(ParseNpy(b, "s").data == s.data);
    REQUIRE(ParseNpy(b, "s").shape.empty());
  }
  SECTION("empty arrays") {
    NpyArray e;
    e.shape = {0, 17, 3};
    const NpyArray back_e = ParseNpy(SerializeNpy(e), "e");
    REQUIRE(back_e.shape == e.shape);
    REQUIRE(back_e.data.empty());
  }
}

TEST_CASE("npy: float64 input is read as float32", "[io][npy]") {
  const std::vector<double> values = {0.1, -2.5, 1e-3, 123456.789, 0.0, -0.0};
  const std::string bytes =
      NpyBytes("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 1, 3), }", RawBytes(values));
  const NpyArray a = ParseNpy(bytes, "f8.npy");
  REQUIRE(a.shape == std::vector<int64_t>{2, 1, 3});
  REQUIRE(a.data.size() == values.size());
  for (size_t i = 0; i < values.size(); ++i) REQUIRE(a.data[i] == static_cast<float>(values[i]));

  SECTION("a float64 motion file") {
    TempDir dir;
    std::vector<double> frames(4 * 17 * 3);
    for (size_t i = 0; i < frames.size(); ++i) frames[i] = 0.001 * static_cast<double>(i);
    std::ofstream(dir.file("m.npy"), std::ios::binary) << NpyBytes(
        "{'descr': '<f8', 'fortran_order': False, 'shape': (4, 17, 3), }", RawBytes(frames));
    const Motion m = ReadNpyMotion(dir.file("m.npy"), MakeHumanoid(), 50.0);
    REQUIRE(m.num_frames() == 4);
    REQUIRE(m.at(3, 16)[2] == static_cast<float>(0.001 * (4 * 51 - 1)));
  }
  SECTION("a float64 value outside the float32 range is an error") {
    const std::string big = NpyBytes("{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }",
                                     RawBytes<double>({1, 1e300}));
    const std::string msg = ParseError(big);
    REQUIRE_THAT(msg, Catch::Contains("float32 range") && Catch::Contains("flat index 1"));
  }
}

TEST_CASE("npy: header variants numpy and other writers produce", "[io][npy]") {
  const std::vector<float> six = {1, 2, 3, 4, 5, 6};
  const std::string data = RawBytes(six);
  auto parses_as = [&](const std::string& dict, std::vector<int64_t> shape, int major = 1,
                       bool pad = true) {
    INFO(dict);
    const NpyArray a = ParseNpy(NpyBytes(dict, data, major, pad), "variant.npy");
    REQUIRE(a.shape == shape);
    REQUIRE(a.data == six);
  };
  parses_as("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", {2, 3});
  parses_as("{'shape': (2, 3), 'fortran_order': False, 'descr': '<f4'}", {2, 3});
  parses_as("{\"fortran_order\":False,\"shape\":(6,),\"descr\":\"<f4\",}", {6});
  parses_as("  {  'descr' : '<f4' ,\n 'fortran_order' : False , 'shape' : ( 1 , 2 , 3 , ) , }  ",
            {1, 2, 3});
  parses_as("{'descr': '<f4', 'fortran_order': False, 'shape': (2L, 3L), }", {2, 3});
  parses_as("{'descr': '<f4', 'fortran_order': False, 'shape': (1, 1, 6)}", {1, 1, 6}, 1, false);
  parses_as("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", {2, 3}, 2);
  parses_as("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", {2, 3}, 3);
  // Byte order "not applicable" / native: numpy reads these as native (little-endian here).
  parses_as("{'descr': '|f4', 'fortran_order': False, 'shape': (6,), }", {6});
  parses_as("{'descr': '=f4', 'fortran_order': False, 'shape': (6,), }", {6});
  // Unknown extra keys are ignored.
  parses_as("{'descr': '<f4', 'fortran_order': False, 'shape': (6,), 'comment': 'x', }", {6});
}

TEST_CASE("npy: every malformed file is a FormatError saying what was expected", "[io][npy]") {
  const std::string six = RawBytes<float>({1, 2, 3, 4, 5, 6});
  auto with_descr = [&](const std::string& descr) {
    return NpyBytes("{'descr': '" + descr + "', 'fortran_order': False, 'shape': (6,), }", six);
  };

  SECTION("magic and version") {
    REQUIRE_THAT(ParseError(""), Catch::Contains("test.npy") && Catch::Contains("magic"));
    REQUIRE_THAT(ParseError("PK\x03\x04 not npy at all"), Catch::Contains("magic"));
    std::string v4 = NpyBytes(F4Dict("(6,)"), six);
    v4[6] = 4;
    REQUIRE_THAT(ParseError(v4),
                 Catch::Contains("version 4.0") && Catch::Contains("1.0, 2.0 or 3.0"));
    v4[6] = 1;
    v4[7] = 1;
    REQUIRE_THAT(ParseError(v4), Catch::Contains("version 1.1"));
    REQUIRE_THAT(ParseError(std::string("\x93NUMPY\x02\x00\x10", 9)), Catch::Contains("truncated"));
  }
  SECTION("dtypes") {
    REQUIRE_THAT(ParseError(with_descr(">f4")), Catch::Contains("'<f4'") &&
                                                    Catch::Contains("found '>f4'") &&
                                                    Catch::Contains("big-endian"));
    REQUIRE_THAT(ParseError(with_descr("<i4")),
                 Catch::Contains("found '<i4'") && Catch::Contains("integer"));
    REQUIRE_THAT(ParseError(with_descr("<u2")), Catch::Contains("integer"));
    REQUIRE_THAT(ParseError(with_descr("|O")), Catch::Contains("object"));
    REQUIRE_THAT(ParseError(with_descr("<f2")), Catch::Contains("float16"));
    REQUIRE_THAT(ParseError(with_descr("|b1")), Catch::Contains("boolean"));
    REQUIRE_THAT(ParseError(with_descr("<c8")), Catch::Contains("complex"));
    REQUIRE_THAT(ParseError(with_descr("<U5")), Catch::Contains("string"));
    REQUIRE_THAT(ParseError(with_descr("")), Catch::Contains("expected dtype"));
    REQUIRE_THAT(ParseError(NpyBytes("{'descr': [('x', '<f4')], 'fortran_order': False, "
                                     "'shape': (6,), }",
                                     six)),
                 Catch::Contains("structured"));
  }
  SECTION("fortran order") {
    REQUIRE_THAT(
        ParseError(NpyBytes("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }", six)),
        Catch::Contains("fortran_order False") && Catch::Contains("found True"));
    REQUIRE_THAT(ParseError(NpyBytes("{'descr': '<f4', 'fortran_order': 0, 'shape': (6,), }", six)),
                 Catch::Contains("fortran_order True or False"));
  }
  SECTION("header dict") {
    REQUIRE_THAT(ParseError(NpyBytes("{'descr': '<f4', 'shape': (6,), }", six)),
                 Catch::Contains("'fortran_order'"));
    REQUIRE_THAT(ParseError(NpyBytes("{'descr': '<f4', 'fortran_order': False}", six)),
                 Catch::Contains("'shape'"));
    REQUIRE_THAT(ParseError(NpyBytes("{'descr': '<f4', 'descr': '<f4', 'fortran_order': False, "
                                     "'shape': (6,)}",
                                     six)),
                 Catch::Contains("duplicate key 'descr'"));
    REQUIRE_THAT(
        ParseError(NpyBytes("{'descr': '<f4', 'fortran_order': False, 'shape': [6]}", six)),
        Catch::Contains("shape tuple") && Catch::Contains("[6]"));
    REQUIRE_THAT(
        ParseError(NpyBytes("{'descr': '<f4', 'fortran_order': False, 'shape': (-6,)}", six)),
        Catch::Contains("non-negative integer"));
    REQUIRE_THAT(
        ParseError(NpyBytes("{'descr': '<f4', 'fortran_order': False, 'shape': (6,)", six)),
        Catch::Contains("expected"));
    REQUIRE_THAT(ParseError(NpyBytes("{'descr': '<f4' 'fortran_order': False}", six)),
                 Catch::Contains("',' or '}'"));
    REQUIRE_THAT(ParseError(NpyBytes("not a dict", six)), Catch::Contains("'{'"));
    REQUIRE_THAT(ParseError(NpyBytes("{'descr': '<f4', 'fortran_order': False, 'shape': "
                                     "(99999999999999999999,)}",
                                     six)),
                 Catch::Contains("64 bits"));
    // Header length beyond the end of the file.
    std::string b = NpyBytes(F4Dict("(6,)"), "");
    b[8] = static_cast<char>(0xff);
    REQUIRE_THAT(ParseError(b), Catch::Contains("truncated header"));
  }
  SECTION("data size must match the shape") {
    const std::string truncated = NpyBytes(F4Dict("(4, 17, 3)"), six);
    REQUIRE_THAT(ParseError(truncated),
                 Catch::Contains("truncated data") && Catch::Contains("expected 816 bytes") &&
                     Catch::Contains("found 24") && Catch::Contains("(4, 17, 3)"));
    REQUIRE_THAT(ParseError(NpyBytes(F4Dict("(5,)"), six)),
                 Catch::Contains("trailing data") && Catch::Contains("expected 20 bytes"));
    // Shapes whose byte count overflows must fail cleanly, not allocate.
    REQUIRE_THAT(ParseError(NpyBytes(F4Dict("(4611686018427387904, 8)"), six)),
                 Catch::Contains("truncated data"));
  }
  SECTION("NaN and Inf are named by index, frame and joint") {
    std::vector<float> v(2 * 17 * 3, 0.5f);
    v[51 + 3 * 5 + 1] = std::numeric_limits<float>::quiet_NaN();
    std::string msg = ParseError(NpyBytes(F4Dict("(2, 17, 3)"), RawBytes(v)));
    REQUIRE_THAT(msg, Catch::Contains("NaN") && Catch::Contains("flat index 67") &&
                          Catch::Contains("frame 1") && Catch::Contains("joint 5") &&
                          Catch::Contains("coordinate y"));
    std::vector<float> w(6, 1.0f);
    w[4] = -std::numeric_limits<float>::infinity();
    msg = ParseError(NpyBytes(F4Dict("(6,)"), RawBytes(w)));
    REQUIRE_THAT(msg, Catch::Contains("Inf") && Catch::Contains("flat index 4"));
  }
}

TEST_CASE("npy: ReadNpyMotion checks the shape against the skeleton", "[io][npy]") {
  TempDir dir;
  auto write = [&](const std::string& name, std::vector<int64_t> shape) {
    NpyArray a;
    a.shape = shape;
    size_t n = 1;
    for (int64_t d : shape) n *= static_cast<size_t>(d);
    a.data.assign(n, 0.25f);
    WriteNpy(dir.file(name), a);
    return dir.file(name);
  };
  auto error_of = [&](const std::string& path) -> std::string {
    try {
      ReadNpyMotion(path, MakeHumanoid(), 30.0);
    } catch (const FormatError& e) {
      return e.what();
    }
    FAIL("expected a FormatError");
    return "";
  };
  REQUIRE_THAT(error_of(write("2d.npy", {4, 51})), Catch::Contains("[T, J, 3]") &&
                                                       Catch::Contains("(4, 51)") &&
                                                       Catch::Contains("2d.npy"));
  REQUIRE_THAT(error_of(write("xy.npy", {4, 17, 2})), Catch::Contains("(4, 17, 2)"));
  REQUIRE_THAT(error_of(write("j16.npy", {4, 16, 3})),
               Catch::Contains("expected 17 joints") && Catch::Contains("(4, 16, 3)"));
  REQUIRE_THAT(error_of(write("empty.npy", {0, 17, 3})), Catch::Contains("at least 1 frame"));
  REQUIRE_THAT(error_of(dir.file("missing.npy")), Catch::Contains("missing.npy"));
  REQUIRE(ReadNpyMotion(write("ok.npy", {4, 17, 3}), MakeHumanoid(), 30.0).num_frames() == 4);
}

TEST_CASE("npy: writer validates and is all-or-nothing", "[io][npy]") {
  TempDir dir;
  NpyArray bad;
  bad.shape = {2, 3};
  bad.data = {1, 2, 3};
  REQUIRE_THROWS_AS(SerializeNpy(bad), std::invalid_argument);
  REQUIRE_THROWS_WITH(WriteNpy(dir.file("bad.npy"), bad),
                      Catch::Contains("expects 6 values, got 3"));
  REQUIRE_FALSE(std::filesystem::exists(dir.file("bad.npy")));
  bad.shape = {-1, 3};
  REQUIRE_THROWS_AS(SerializeNpy(bad), std::invalid_argument);
  NpyArray nan;
  nan.shape = {2};
  nan.data = {1, std::numeric_limits<float>::quiet_NaN()};
  REQUIRE_THROWS_WITH(SerializeNpy(nan),
                      Catch::Contains("finite") && Catch::Contains("flat index 1"));

  SECTION("a failed write keeps the old file") {
    NpyArray good;
    good.shape = {3};
    good.data = {1, 2, 3};
    const std::string path = dir.file("keep.npy");
    WriteNpy(path, good);
    REQUIRE_THROWS(WriteNpy(path, bad));
    REQUIRE(ReadNpy(path).data == good.data);
    size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
      (void)entry;
      ++files;
    }
    REQUIRE(files == 1);  // no temporary left behind
  }
  SECTION("an unwritable destination throws FormatError and leaves no file") {
    // A folder path that runs through a regular file cannot be created, even by root.
    std::ofstream(dir.file("plain_file")) << "x";
    const std::string path = dir.file("plain_file") + "/sub/out.npy";
    REQUIRE_THROWS_AS(WriteNpyMotion(path, MakeWalkingMotion(3)), FormatError);
    REQUIRE_FALSE(std::filesystem::exists(path));
  }
}

}  // namespace
}  // namespace motionfork
