// Mutation ("fuzz") tests of the .npy and CSV readers: thousands of corrupted copies of valid
// files, with a fixed seed. Each must either read as finite data or throw FormatError; any other
// exception (or a crash) is a bug.
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <typeinfo>
#include <vector>

#include "core/error.h"
#include "io/csv.h"
#include "io/npy.h"
#include "memory_limit.h"
#include "test_support.h"

namespace motionfork {
namespace {

using testing::MakeHumanoid;
using testing::MakeWalkingMotion;
using testing::TempDir;

// Bytes that matter to the parsers: digits, separators, quotes, brackets, signs, line breaks.
constexpr char kInterestingChars[] = "0123456789,.;:'\"()[]{} \t\r\n-+eE#xyzLnaNiIfFTrue\0\xff\x93";
const std::string kInteresting(kInterestingChars, sizeof(kInterestingChars) - 1);

std::string Mutate(const std::string& base, std::mt19937& rng, size_t hot_prefix) {
  std::string s = base;
  auto pick = [&](size_t n) {
    return n == 0 ? size_t{0} : std::uniform_int_distribution<size_t>(0, n - 1)(rng);
  };
  // Positions within the first hot_prefix bytes (the header) are chosen half of the time.
  auto position = [&](size_t n) {
    if (hot_prefix > 0 && rng() % 2 == 0) return pick(std::min(n, hot_prefix));
    return pick(n);
  };
  const int mutations = 1 + static_cast<int>(rng() % 3);
  for (int m = 0; m < mutations && !s.empty(); ++m) {
    switch (rng() % 6) {
      case 0:  // truncate
        s.resize(pick(s.size() + 1));
        break;
      case 1:  // random byte
        s[position(s.size())] = static_cast<char>(rng() & 0xff);
        break;
      case 2:  // an interesting byte
        s[position(s.size())] = kInteresting[pick(kInteresting.size())];
        break;
      case 3: {  // delete a range
        const size_t at = position(s.size());
        s.erase(at, 1 + pick(8));
        break;
      }
      case 4: {  // insert interesting bytes
        const size_t at = position(s.size() + 1);
        std::string chunk;
        for (size_t k = 0, n = 1 + pick(4); k < n; ++k)
          chunk += kInteresting[pick(kInteresting.size())];
        s.insert(std::min(at, s.size()), chunk);
        break;
      }
      default: {  // duplicate a range
        const size_t at = position(s.size());
        const std::string piece = s.substr(at, 1 + pick(16));
        s.insert(at, piece);
        break;
      }
    }
  }
  return s;
}

bool AllFinite(const std::vector<float>& v) {
  for (float x : v) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

TEST_CASE("mutation: corrupted .npy bytes give finite data or FormatError", "[io][npy][mutation]") {
  NpyArray base;
  base.shape = {6, 17, 3};
  base.data = MakeWalkingMotion(6).positions();
  const std::string valid = SerializeNpy(base);
  // A float64 variant too, built from the float32 one.
  const size_t data_begin =
      10 + (static_cast<unsigned char>(valid[8]) | (static_cast<unsigned char>(valid[9]) << 8));
  std::string valid_f8 = valid.substr(0, data_begin);
  valid_f8.replace(valid_f8.find("<f4"), 3, "<f8");
  for (float x : base.data) {
    const double d = x;
    valid_f8.append(reinterpret_cast<const char*>(&d), sizeof(d));
  }
  REQUIRE(ParseNpy(valid_f8, "f8").data == base.data);

  TempDir dir;
  const auto skeleton = MakeHumanoid();
  std::mt19937 rng(20240611);
  const auto start = std::chrono::steady_clock::now();
  int ok = 0, rejected = 0;
  for (int i = 0; i < 20000; ++i) {
    const std::string bytes = Mutate(i % 3 == 0 ? valid_f8 : valid, rng, 128);
    try {
      if (i % 10 == 0) {
        // Through the file reader and the motion checks too.
        const std::string path = dir.file("m.npy");
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
        const Motion m = ReadNpyMotion(path, i % 20 == 0 ? skeleton : nullptr, 30.0);
        REQUIRE(AllFinite(m.positions()));
      } else {
        const NpyArray a = ParseNpy(bytes, "mutated.npy");
        size_t n = 1;
        for (int64_t d : a.shape) n *= static_cast<size_t>(d);
        REQUIRE(n == a.data.size());
        REQUIRE(AllFinite(a.data));
      }
      ++ok;
    } catch (const FormatError&) {
      ++rejected;
    } catch (const std::exception& e) {
      FAIL("iteration " << i << ": unexpected " << typeid(e).name() << ": " << e.what());
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO(ok << " read, " << rejected << " rejected in " << seconds << " s");
  CHECK(ok > 0);
  CHECK(rejected > 0);
  CHECK(seconds < 20.0);
}

TEST_CASE("mutation: corrupted CSV bytes give finite data or FormatError", "[io][csv][mutation]") {
  TempDir dir;
  WriteCsvMotion(dir.file("base.csv"), MakeWalkingMotion(5));
  std::string valid;
  {
    std::ifstream in(dir.file("base.csv"), std::ios::binary);
    valid.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const size_t header_end = valid.find('\n', valid.find('\n') + 1) + 1;
  const auto skeleton = MakeHumanoid();
  std::mt19937 rng(977);
  const auto start = std::chrono::steady_clock::now();
  int ok = 0, rejected = 0;
  const std::string path = dir.file("m.csv");
  for (int i = 0; i < 8000; ++i) {
    const std::string bytes = Mutate(valid, rng, i % 2 == 0 ? header_end : 0);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    try {
      const Motion m = ReadCsvMotion(path, i % 3 == 0 ? nullptr : skeleton, 30.0);
      REQUIRE(m.num_frames() >= 1);
      REQUIRE(m.fps() > 0);
      REQUIRE(AllFinite(m.positions()));
      ++ok;
    } catch (const FormatError&) {
      ++rejected;
    } catch (const std::exception& e) {
      FAIL("iteration " << i << ": unexpected " << typeid(e).name() << ": " << e.what());
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO(ok << " read, " << rejected << " rejected in " << seconds << " s");
  CHECK(ok > 0);
  CHECK(rejected > 0);
  CHECK(seconds < 20.0);
}

}  // namespace
}  // namespace motionfork

namespace motionfork {
namespace {

// Files that claim far more than they hold, or hold nothing but line breaks: each is refused
// (FormatError) in a process capped at 1 GiB, with memory proportional to its bytes.
TEST_CASE("mutation: .npy and CSV size claims are checked before allocating, in 1 GiB",
          "[io][npy][csv][mutation][memory]") {
  TempDir dir;
  // A header claiming a billion frames over 12 bytes of data.
  NpyArray small;
  small.shape = {1, 1, 3};
  small.data = {1, 2, 3};
  std::string npy = SerializeNpy(small);
  // The same header length: 9 padding spaces before the header's final '\n' make room.
  const size_t data_begin =
      10 + (static_cast<unsigned char>(npy[8]) | (static_cast<unsigned char>(npy[9]) << 8));
  REQUIRE(npy.substr(data_begin - 10, 9) == std::string(9, ' '));
  npy.erase(data_begin - 10, 9);
  const size_t shape_at = npy.find("(1, 1, 3)");
  REQUIRE(shape_at != std::string::npos);
  npy.replace(shape_at, 9, "(1000000000, 1, 3)");
  REQUIRE_NOTHROW(ParseNpy(SerializeNpy(small), "small.npy"));
  const std::string claim = dir.file("claim.npy");
  std::ofstream(claim, std::ios::binary) << npy;
  testing::LimitedRun r = testing::RunWithMemoryLimit([&] { ReadNpyMotion(claim, nullptr, 30); });
  INFO(r.message);
  CHECK(r.outcome == testing::LimitedOutcome::kFormatError);
  CHECK_THAT(r.message, Catch::Contains("expected"));

  // 50 MB of blank lines: no header, and no memory per line.
  const std::string blank = dir.file("blank.csv");
  std::ofstream(blank, std::ios::binary) << std::string(50u << 20, '\n');
  r = testing::RunWithMemoryLimit([&] { ReadCsvMotion(blank, nullptr, 30); }, rlim_t{512} << 20);
  INFO(r.message);
  CHECK(r.outcome == testing::LimitedOutcome::kFormatError);
  CHECK_THAT(r.message, Catch::Contains("no header line"));

  // A header naming more joints than a motion may have.
  std::string wide;
  for (int j = 0; j < 1100; ++j) wide += std::string(j ? "," : "") + "j" + std::to_string(j) + ".x";
  const std::string wide_csv = dir.file("wide.csv");
  std::ofstream(wide_csv, std::ios::binary) << wide << "\n";
  r = testing::RunWithMemoryLimit([&] { ReadCsvMotion(wide_csv, nullptr, 30); });
  CHECK(r.outcome == testing::LimitedOutcome::kFormatError);

  // A 600 MB sparse file (zeros) given as a CSV is refused from its first bytes.
  const std::string sparse = dir.file("sparse.csv");
  std::ofstream(sparse, std::ios::binary).put('\0');
  std::filesystem::resize_file(sparse, uint64_t{600} << 20);
  r = testing::RunWithMemoryLimit([&] { ReadCsvMotion(sparse, nullptr, 30); }, rlim_t{256} << 20);
  INFO(r.message);
  CHECK(r.outcome == testing::LimitedOutcome::kFormatError);
  CHECK_THAT(r.message, Catch::Contains("binary data"));
}

}  // namespace
}  // namespace motionfork
