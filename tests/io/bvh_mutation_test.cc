// BVH reader robustness: thousands of damaged variants of valid files (fixed seed). Each must
// either read with finite positions or throw FormatError; any other exception, a crash or a hang
// fails.
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "io/bvh.h"
#include "memory_limit.h"
#include "test_support.h"

namespace motionfork {
namespace {

// A valid BVH: a small chain-and-branch skeleton with the given channel lists, random values.
std::string MakeValidBvh(const std::vector<std::string>& root_channels,
                         const std::vector<std::string>& joint_channels, int frames,
                         const std::string& frame_time, const std::string& newline, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> val(-180, 180);
  const char* names[] = {"Hips", "Spine", "Head", "Arm_L", "Hand_L", "Leg_R", "Foot_R"};
  const int parents[] = {-1, 0, 1, 1, 3, 0, 5};
  const double offsets[][3] = {{0, 90, 0}, {0, 20, 0},  {0, 30, 2}, {15, 25, 0},
                               {25, 0, 0}, {-9, -5, 0}, {0, -80, 0}};
  const int n = 7;
  std::string s = "HIERARCHY" + newline;
  int channels = 0;
  std::vector<int> depth(n, 0);
  // Writes joint j and its subtree.
  std::function<void(int)> write = [&](int j) {
    const std::string ind(2 * depth[j], ' ');
    s += ind + (j == 0 ? "ROOT " : "JOINT ") + names[j] + newline + ind + "{" + newline;
    s += ind + "  OFFSET " + std::to_string(offsets[j][0]) + " " + std::to_string(offsets[j][1]) +
         " " + std::to_string(offsets[j][2]) + newline;
    const auto& ch = j == 0 ? root_channels : joint_channels;
    s += ind + "  CHANNELS " + std::to_string(ch.size());
    for (const auto& c : ch) s += " " + c;
    s += newline;
    channels += static_cast<int>(ch.size());
    bool leaf = true;
    for (int k = 0; k < n; ++k) {
      if (parents[k] == j) {
        leaf = false;
        depth[k] = depth[j] + 1;
        write(k);
      }
    }
    if (leaf) {
      s += ind + "  End Site" + newline + ind + "  {" + newline + ind + "    OFFSET 0 5 0" +
           newline + ind + "  }" + newline;
    }
    s += ind + "}" + newline;
  };
  write(0);
  s += "MOTION" + newline + "Frames: " + std::to_string(frames) + newline +
       "Frame Time: " + frame_time + newline;
  char buf[32];
  for (int t = 0; t < frames; ++t) {
    for (int c = 0; c < channels; ++c) {
      std::snprintf(buf, sizeof buf, "%s%.5g", c ? " " : "", val(rng));
      s += buf;
    }
    s += newline;
  }
  return s;
}

std::vector<std::string> SplitLines(const std::string& s) {
  std::vector<std::string> lines;
  size_t b = 0;
  while (b < s.size()) {
    size_t e = s.find('\n', b);
    if (e == std::string::npos) e = s.size() - 1;
    lines.push_back(s.substr(b, e - b + 1));
    b = e + 1;
  }
  return lines;
}

std::string JoinLines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l;
  return s;
}

// One random mutation of text.
std::string Mutate(const std::string& text, std::mt19937& rng) {
  auto pick = [&](size_t n) { return n == 0 ? size_t{0} : static_cast<size_t>(rng() % n); };
  std::string s = text;
  switch (rng() % 9) {
    case 0:  // truncate anywhere
      s.resize(pick(s.size() + 1));
      break;
    case 1: {  // corrupt a few bytes with any byte value (NUL included)
      const int k = 1 + static_cast<int>(rng() % 4);
      for (int i = 0; i < k && !s.empty(); ++i) s[pick(s.size())] = static_cast<char>(rng() & 0xff);
      break;
    }
    case 2: {  // delete a line
      auto lines = SplitLines(s);
      if (!lines.empty()) lines.erase(lines.begin() + pick(lines.size()));
      s = JoinLines(lines);
      break;
    }
    case 3: {  // duplicate a line
      auto lines = SplitLines(s);
      if (!lines.empty()) {
        const size_t i = pick(lines.size());
        lines.insert(lines.begin() + i, lines[i]);
      }
      s = JoinLines(lines);
      break;
    }
    case 4: {  // digits -> letters
      std::vector<size_t> digits;
      for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] >= '0' && s[i] <= '9') digits.push_back(i);
      }
      const int k = 1 + static_cast<int>(rng() % 3);
      for (int i = 0; i < k && !digits.empty(); ++i) {
        s[digits[pick(digits.size())]] = "aeEfxInN"[rng() % 8];
      }
      break;
    }
    case 5: {  // a number token replaced by a non-finite or extreme value
      static const char* kBad[] = {"nan",      "NaN",   "inf",      "-inf",
                                   "infinity", "1e999", "-1e400",   "1e-400",
                                   "1e300",    "-1e38", "nan(123)", "+inf",
                                   "0x1p3",    "1e",    "-",        ".",
                                   "+",        "--1",   "1..2",     "9999999999999999999999"};
      std::vector<std::pair<size_t, size_t>> numbers;  // [begin, end)
      for (size_t i = 0; i < s.size();) {
        if ((s[i] >= '0' && s[i] <= '9') || s[i] == '-') {
          size_t e = i;
          while (e < s.size() && s[e] != ' ' && s[e] != '\n' && s[e] != '\r' && s[e] != '\t') ++e;
          numbers.emplace_back(i, e);
          i = e;
        } else {
          ++i;
        }
      }
      if (!numbers.empty()) {
        const auto [b, e] = numbers[pick(numbers.size())];
        s.replace(b, e - b, kBad[rng() % (sizeof kBad / sizeof *kBad)]);
      }
      break;
    }
    case 6: {  // swap two lines
      auto lines = SplitLines(s);
      if (lines.size() > 1) std::swap(lines[pick(lines.size())], lines[pick(lines.size())]);
      s = JoinLines(lines);
      break;
    }
    case 7: {  // insert a structural token somewhere
      static const char* kTokens[] = {"{",
                                      "}",
                                      " JOINT X ",
                                      " End Site ",
                                      "\n",
                                      "\r",
                                      " ",
                                      "CHANNELS 9",
                                      "MOTION\n",
                                      "ROOT R {",
                                      "\t",
                                      " 1 ",
                                      "OFFSET 1 2 3",
                                      "Frames: 99999999999",
                                      "Frame Time: 0"};
      s.insert(pick(s.size() + 1), kTokens[rng() % (sizeof kTokens / sizeof *kTokens)]);
      break;
    }
    default: {  // delete a random span
      const size_t b = pick(s.size() + 1);
      s.erase(b, pick(64));
      break;
    }
  }
  return s;
}

TEST_CASE("bvh: mutated files either read cleanly or throw FormatError", "[io][bvh][fuzz]") {
  const std::vector<std::string> pos_zxy = {"Xposition", "Yposition", "Zposition",
                                            "Zrotation", "Xrotation", "Yrotation"};
  const std::vector<std::string> zyx = {"Zrotation", "Yrotation", "Xrotation"};
  const std::vector<std::string> yx = {"Yrotation", "Xrotation"};
  const std::vector<std::string> bases = {
      MakeValidBvh(pos_zxy, pos_zxy, 6, "0.0333333", "\n", 1),  // Bandai-like
      MakeValidBvh({"Xposition", "Yposition", "Zposition", "Zrotation", "Yrotation", "Xrotation"},
                   zyx, 5, "0.008333", "\n", 2),        // CMU-like
      MakeValidBvh(pos_zxy, yx, 4, "0.04", "\r\n", 3),  // CRLF, 2 channels
  };
  // The bases themselves read.
  for (const auto& b : bases) REQUIRE_NOTHROW(ReadBvhText(b, "base.bvh"));

  std::mt19937 rng(20240611);
  const auto start = std::chrono::steady_clock::now();
  int ok = 0, format_errors = 0, variants = 0;
  for (int i = 0; i < 30000; ++i) {
    std::string s = bases[i % bases.size()];
    const int rounds = 1 + static_cast<int>(rng() % 3);
    for (int r = 0; r < rounds; ++r) s = Mutate(s, rng);
    ++variants;
    BvhOptions opt;
    opt.include_end_sites = (i % 2) == 1;
    try {
      const Motion m = ReadBvhText(s, "mutant.bvh", opt);
      bool finite = true;
      for (float v : m.positions()) finite = finite && std::isfinite(v);
      if (!finite) {
        INFO("variant " << i << ":\n" << s);
        FAIL("non-finite position");
      }
      if (!(m.fps() > 0) || !std::isfinite(m.fps())) {
        INFO("variant " << i << ":\n" << s);
        FAIL("bad fps");
      }
      ++ok;
    } catch (const FormatError& e) {
      const std::string msg = e.what();
      if (msg.rfind("mutant.bvh:", 0) != 0) {
        INFO("variant " << i << ": " << msg);
        FAIL("message does not start with the file name");
      }
      ++format_errors;
    } catch (const std::exception& e) {
      INFO("variant " << i << ":\n" << s);
      FAIL(std::string("unexpected exception type: ") + e.what());
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("bvh mutation: %d variants, %d read, %d FormatError, %.2f s\n", variants, ok,
              format_errors, seconds);
  CHECK(ok > 100);  // some mutations are harmless (e.g. digit changes inside numbers)
  CHECK(format_errors > 1000);
}

// Files that claim far more than they hold: each is refused (FormatError naming the limit or the
// missing bytes) in a process capped at 1 GiB, before anything is allocated for the claim.
TEST_CASE("bvh: size claims are checked against the bytes present, in 1 GiB",
          "[io][bvh][fuzz][memory]") {
  const std::string no_channels =  // 81 bytes claiming 89 million frames of the rest pose
      "HIERARCHY\nROOT R\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 89000000\n"
      "Frame Time: 0.1\n";
  REQUIRE(no_channels.size() < 90);
  std::string header =
      MakeValidBvh({"Xposition", "Yposition", "Zposition"}, {"Zrotation"}, 1, "0.0333333", "\n", 4);
  header.resize(header.find("Frames:"));
  const std::vector<std::pair<std::string, std::string>> claims = {
      {no_channels, "limit of 10000000 frames"},
      {no_channels.substr(0, no_channels.find("89000000")) + "9000000\nFrame Time: 0.1\n",
       "without channels"},
      {header + "Frames: 9999999\nFrame Time: 0.03\n1 2 3 4 5 6 7 8 9\n", "ends after 1"},
      {header + "Frames: 999999999999\nFrame Time: 0.03\n", "limit of 10000000 frames"},
  };
  for (const auto& [text, phrase] : claims) {
    testing::TempDir dir;
    const std::string path = dir.file("claim.bvh");
    std::ofstream(path, std::ios::binary) << text;
    const testing::LimitedRun r = testing::RunWithMemoryLimit([&] { ReadBvhFile(path); });
    INFO(text << "\n-> " << r.message);
    CHECK(r.outcome == testing::LimitedOutcome::kFormatError);
    CHECK_THAT(r.message, Catch::Contains(phrase));
  }
  // A 600 MB sparse file (zeros) is refused from its first bytes, not read whole.
  testing::TempDir dir;
  const std::string sparse = dir.file("sparse.bvh");
  std::ofstream(sparse, std::ios::binary).put('\0');
  std::filesystem::resize_file(sparse, uint64_t{600} << 20);
  const testing::LimitedRun r =
      testing::RunWithMemoryLimit([&] { ReadBvhFile(sparse); }, rlim_t{256} << 20);
  INFO(r.message);
  CHECK(r.outcome == testing::LimitedOutcome::kFormatError);
  CHECK_THAT(r.message, Catch::Contains("expected 'HIERARCHY'"));
}

}  // namespace
}  // namespace motionfork
