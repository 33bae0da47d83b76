#include "bundle/bundle_files.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "bundle/manifest.h"
#include "core/error.h"
#include "io/file_util.h"
#include "test_support.h"

namespace motionfork {
namespace {

const char* kSkeletonYaml =
    "skeleton:\n"
    "  name: tiny\n"
    "  joints: [[root, ~], [hip, root]]\n";

// A manifest with the shared keys and the checksums WriteBundle hands over.
std::string TinyManifest(const BundleChecksums& sums) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  EmitManifestFormat(out, {"motionfork-test-1", "tiny", 30, {}, {}});
  EmitManifestChecksums(out, sums);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

TEST_CASE("bundle: weights are written with their checksum and a mismatch names the file") {
  testing::TempDir tmp;
  const std::string dir = tmp.file("bundle");
  WriteBundle(dir, {{"w.bin", "weights"}}, "m.yaml", TinyManifest);
  const std::string manifest = tmp.file("bundle/m.yaml");
  const ManifestHeader h =
      ParseManifestHeader(manifest, LoadManifestFile(manifest), "motionfork-test-1", {true, false});
  CHECK(h.protocol == "tiny");
  CHECK(h.fps == 30);
  REQUIRE(h.checksums.count("w.bin") == 1);
  CHECK(h.checksums.at("w.bin") == BundleChecksum("weights"));
  CHECK(ReadBundleFile(dir, "w.bin", h.checksums, "m.yaml") == "weights");

  // Rewriting an existing folder keeps its other files.
  WriteFileAtomically(tmp.file("bundle/keep.txt"), "kept");
  WriteBundle(dir, {{"w.bin", "weights 2"}}, "m.yaml", TinyManifest);
  CHECK(ReadFileBytes(tmp.file("bundle/keep.txt")) == "kept");
  CHECK(std::distance(std::filesystem::directory_iterator(tmp.path()),
                      std::filesystem::directory_iterator()) == 1);

  WriteFileAtomically(tmp.file("bundle/w.bin"), "damaged");
  try {
    ReadBundleFile(dir, "w.bin", h.checksums, "m.yaml");
    FAIL("a damaged file was accepted");
  } catch (const FormatError& e) {
    CHECK_THAT(e.what(), Catch::Contains("w.bin") && Catch::Contains("checksum") &&
                             Catch::Contains("m.yaml"));
  }
  // Bundles written before checksums record none: their files load unchecked.
  CHECK(ReadBundleFile(dir, "w.bin", {}, "m.yaml") == "damaged");
}

TEST_CASE("bundle: a manifest missing a shared key names the key") {
  const std::string text =
      std::string("format: motionfork-test-1\nprotocol:\n  name: tiny\n") + kSkeletonYaml;
  try {
    ParseManifestHeader("m.yaml", YAML::Load(text), "motionfork-test-1");
    FAIL("a manifest without protocol.fps was accepted");
  } catch (const FormatError& e) {
    CHECK_THAT(e.what(), Catch::Contains("m.yaml") && Catch::Contains("'fps'"));
  }
  CHECK_THROWS_WITH(ParseManifestHeader("m.yaml", YAML::Load(text), "motionfork-other-1"),
                    Catch::Contains("format") && Catch::Contains("motionfork-other-1"));
}

TEST_CASE("bundle: missing bundle files are named") {
  testing::TempDir tmp;
  CHECK_THROWS_WITH(RequireBundleFiles(tmp.file("none"), "HG-VAE", {"hgvae.yaml", "hgvae.pt"}),
                    Catch::Contains("HG-VAE bundle folder not found"));
  CHECK_THROWS_WITH(
      RequireBundleFiles(tmp.path().string(), "HG-VAE", {"hgvae.yaml", "hgvae.pt"}),
      Catch::Contains("hgvae.yaml") && Catch::Contains("expected hgvae.yaml and hgvae.pt"));
}

}  // namespace
}  // namespace motionfork
