// Mutation ("fuzz") tests of the .npy and CSV readers: thousands of corrupted copies of valid
// files, with a fixed seed. Each must either read as finite data or throw FormatError; any other
// exception (or a crash) is a bug.
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <typeinfo>
#include <vector>

#include "core/error.h"
#include "io/csv.h"
#include "io/npy.h"
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
