// Damaged and edited model bundles end to end: every case exits 2 naming the file and what is
// wrong, never crashes, never forecasts from a bundle that is not what its manifest says.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "motionfork/motionfork.h"
#include "run_motionfork.h"

namespace motionfork {
namespace {

namespace fs = std::filesystem;
using testing::Motionfork;

const fs::path kShipped = fs::path(MOTIONFORK_SOURCE_DIR) / "models" / "bandai";

std::string ReadText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteText(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// A scratch folder (emptied) under the build tree.
fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::path(MOTIONFORK_BINARY_DIR) / "robustness" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The shipped generator bundle's files (not hgvae/, dvae/, prior/) copied into dir/model.
fs::path CopyGenerator(const fs::path& dir) {
  const fs::path model = dir / "model";
  fs::create_directories(model);
  for (const char* f : {"model.yaml", "generator.pt", "constraints.yaml"})
    fs::copy_file(kShipped / f, model / f);
  return model;
}

// Replaces the first `from` in file by `to` (which must be there).
void Edit(const fs::path& file, const std::string& from, const std::string& to) {
  std::string text = ReadText(file);
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  text.replace(at, from.size(), to);
  WriteText(file, text);
}

std::string History(const fs::path& dir) {
  const fs::path walk = dir / "walk.npy";
  if (!fs::exists(walk)) REQUIRE(Motionfork("synth walk -o " + walk.string()).status == 0);
  return walk.string();
}

testing::Run Predict(const fs::path& model, const fs::path& dir) {
  return Motionfork("predict --model " + model.string() + " --history " + History(dir) +
                    " -k 3 -o " + (dir / "out").string());
}

}  // namespace

TEST_CASE("a model.yaml edited to sizes the weights do not have is refused, naming both") {
  const std::vector<std::pair<std::string, std::string>> edits = {
      {"hidden: 256", "hidden: 128"}, {"nz: 64", "nz: 4096"},
      {"nz: 64", "nz: 32"},           {"blocks: 4", "blocks: 2"},
      {"t_his: 15", "t_his: 16"},     {"batch_norm: true", "batch_norm: false"},
      {"n_pre: 8", "n_pre: 10"},      {"[Head, Neck]", "[Head, Chest]"}};
  for (const auto& [from, to] : edits) {
    DYNAMIC_SECTION(to) {
      const fs::path dir = Scratch("edited");
      const fs::path model = CopyGenerator(dir);
      Edit(model / "model.yaml", from, to);
      const testing::Run r = Predict(model, dir);
      INFO(r.output);
      CHECK(r.status == 2);
      CHECK(r.output.find("model.yaml") != std::string::npos);
      CHECK(r.output.find(to) != std::string::npos);  // the line that no longer fits
      CHECK(!fs::exists(dir / "out.npy"));
      CHECK(!fs::exists(dir / "out.json"));
    }
  }
}

TEST_CASE("flipped bytes in generator.pt are refused by the checksum in model.yaml") {
  const fs::path dir = Scratch("flipped");
  const fs::path model = CopyGenerator(dir);
  std::string bytes = ReadText(model / "generator.pt");
  std::mt19937 rng(7);
  for (int i = 0; i < 50; ++i) bytes[rng() % bytes.size()] ^= 0x5a;
  WriteText(model / "generator.pt", bytes);
  const testing::Run r = Predict(model, dir);
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("generator.pt") != std::string::npos);
  CHECK(r.output.find("checksum") != std::string::npos);
  CHECK(!fs::exists(dir / "out.npy"));
}

TEST_CASE("sizes beyond the documented bounds are refused before the network is built") {
  const fs::path dir = Scratch("bounds");
  const fs::path model = CopyGenerator(dir);
  Edit(model / "model.yaml", "hidden: 256", "hidden: 20000");
  const testing::Run r = Predict(model, dir);
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("hidden") != std::string::npos);
  CHECK(r.output.find("4096") != std::string::npos);
}

TEST_CASE("a bundle without checksums is refused until 'bundle upgrade' rewrites it") {
  const fs::path dir = Scratch("legacy");
  const fs::path model = CopyGenerator(dir);
  std::string yaml = ReadText(model / "model.yaml");
  const size_t at = yaml.find("checksums:");
  REQUIRE(at != std::string::npos);
  const size_t end = yaml.find("\ninfo:", at);
  yaml.erase(at, end == std::string::npos ? std::string::npos : end + 1 - at);
  WriteText(model / "model.yaml", yaml);
  testing::Run r = Predict(model, dir);
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("no checksum of generator.pt") != std::string::npos);
  CHECK(r.output.find("bundle upgrade") != std::string::npos);
  r = Motionfork("bundle upgrade " + model.string());
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(r.output.find("generator") != std::string::npos);
  CHECK(Predict(model, dir).status == 0);
}

}  // namespace motionfork

namespace motionfork {
namespace {

// One mutation of a bundle's files (seeded): a random value of the manifest replaced by one of
// the values that break parsers and sizes, or 1 to 50 random bytes of the weights flipped.
// Returns the manifest key changed ("" for the weights).
std::string Mutate(const fs::path& manifest, const fs::path& weights, std::mt19937& rng) {
  std::string key;
  if (rng() % 2 == 0) {
    std::vector<std::string> lines;
    std::istringstream in(ReadText(manifest));
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    static const std::vector<std::string> values = {"0",   "-1",   "1",    "2",      "3",
                                                    "255", "257",  "4097", "1e9",    "abc",
                                                    "",    "true", "0.5",  "[1, 2]", "~"};
    for (int tries = 0; tries < 100; ++tries) {
      std::string& l = lines[rng() % lines.size()];
      const size_t colon = l.find(": ");
      if (colon == std::string::npos) continue;
      key = l.substr(l.find_first_not_of(' '), colon - l.find_first_not_of(' '));
      l = l.substr(0, colon + 2) + values[rng() % values.size()];
      break;
    }
    std::string text;
    for (const std::string& l : lines) text += l + "\n";
    WriteText(manifest, text);
  } else {
    std::string bytes = ReadText(weights);
    const int flips = 1 + static_cast<int>(rng() % 50);
    for (int i = 0; i < flips; ++i)
      bytes[rng() % bytes.size()] ^= static_cast<char>(1 + rng() % 255);
    WriteText(weights, bytes);
  }
  return key;
}

// Runs `cases` mutations of the bundle in `dir` (manifest + weights); after each, `use` loads the
// bundle and returns its output, or throws. Loading may only succeed with the original output,
// but where a key of `settings` changed (settings a user may edit in the manifest, which the
// weights' signature leaves out) with some finite output.
template <typename Use>
void Fuzz(const fs::path& dir, const char* manifest, const char* weights, int cases, Use use,
          const std::set<std::string>& settings = {}) {
  const std::string yaml = ReadText(dir / manifest), pt = ReadText(dir / weights);
  const std::vector<float> expected = use();
  std::mt19937 rng(20261203);
  int refused = 0;
  for (int c = 0; c < cases; ++c) {
    WriteText(dir / manifest, yaml);
    WriteText(dir / weights, pt);
    const std::string key = Mutate(dir / manifest, dir / weights, rng);
    try {
      const std::vector<float> got = use();
      INFO("case " << c << ": loaded; manifest:\n" << ReadText(dir / manifest));
      if (settings.count(key)) {
        for (float x : got) REQUIRE(std::isfinite(x));
        continue;
      }
      REQUIRE(got == expected);
    } catch (const std::exception& e) {
      ++refused;
      INFO("case " << c);
      REQUIRE(std::string(e.what()).size() > 10);
    }
  }
  WriteText(dir / manifest, yaml);
  WriteText(dir / weights, pt);
  CHECK(refused > cases / 2);
}

}  // namespace

TEST_CASE("bundle fuzzer: mutated generator, HG-VAE and Motion-DVAE bundles never load as others") {
  const fs::path dir = Scratch("fuzz");
  const fs::path model = CopyGenerator(dir);
  const std::vector<float> history = Model::Load(model.string()).ReadMotion(History(dir));
  Fuzz(model, "model.yaml", "generator.pt", 200, [&] {
    return Model::Load(model.string()).Predict(history, {2, 0, {}, true}).positions;
  });
  std::vector<float> gappy = history;
  for (size_t i = 7; i < gappy.size(); i += 11) {
    if (i % (17 * 3) >= 3) gappy[i] = std::nanf("");  // never the root (joint 0)
  }
  fs::copy(kShipped / "hgvae", dir / "hgvae");
  // The imputation defaults and the refiner's adaptation are settings (HgvaeSignature).
  Fuzz(dir / "hgvae", "hgvae.yaml", "hgvae.pt", 60,
       [&] { return Imputer::Load((dir / "hgvae").string()).Impute(gappy).positions; },
       {"steps", "lr", "objective", "refiner_adapt_values", "refiner_smooth"});
  fs::copy(kShipped / "dvae", dir / "dvae");
  Fuzz(dir / "dvae", "dvae.yaml", "dvae.pt", 60,
       [&] { return Denoiser::Load((dir / "dvae").string()).Denoise(history); });
}

}  // namespace motionfork
