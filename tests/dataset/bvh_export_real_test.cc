// BVH export on real motion capture (../shared/data/bandai, bandai-1.tar.xz only, read in place):
// positions -> BVH -> positions within 1 mm, on the protocol's 17 joints (through the dataset
// loader) and on the files' own 22 joints.
#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "core/pose_fitting.h"
#include "core/pose_fixtures.h"
#include "dataset/dataset.h"
#include "io/archive.h"
#include "io/bvh.h"
#include "io/bvh_writer.h"
#include "test_support.h"

namespace motionfork {
namespace {

struct RoundTrip {
  int clips = 0;
  long long frames = 0;
  double max_error = 0;    // metres
  std::string translated;  // joints with their own translation, over all clips
};

void Measure(const Motion& m, const testing::TempDir& dir, RoundTrip* r) {
  const std::string path = dir.file("clip.bvh");
  WriteBvh(path, m);
  const Motion back = ReadBvhFile(path);
  REQUIRE(back.skeleton().SameStructure(m.skeleton()));
  r->max_error = std::max(r->max_error, testing::MaxDistance(back, m));
  r->clips += 1;
  r->frames += m.num_frames();
  const PoseFit fit = FitPose(m);
  for (int j = 1; j < fit.num_joints; ++j) {
    const std::string name = " " + m.skeleton().joint_name(j);
    if (fit.translated[j] && r->translated.find(name) == std::string::npos) r->translated += name;
  }
}

std::string Report(const std::string& what, const RoundTrip& r) {
  std::ostringstream s;
  s << what << ": " << r.clips << " clips, " << r.frames << " frames, max round-trip error "
    << r.max_error * 1000 << " mm; joints with translations of their own:"
    << (r.translated.empty() ? " none" : r.translated);
  return s.str();
}

TEST_CASE("bvh export on bandai clips: positions -> BVH -> positions within 1 mm") {
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  // A data folder holding only the small archive (and the split file), linked, not copied.
  testing::TempDir folder, out;
  std::filesystem::create_symlink(data + "/bandai-1.tar.xz", folder.path() / "bandai-1.tar.xz");
  std::filesystem::create_symlink(data + "/split.tsv", folder.path() / "split.tsv");
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", "bandai"));
  const SkeletonConfig s =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", p.skeleton));
  const Dataset ds = LoadDataset(p, s, folder.path().string());
  REQUIRE(ds.clips.size() > 100);
  RoundTrip protocol;
  for (size_t i = 0; i < ds.clips.size(); i += 29) Measure(ds.clips[i].motion, out, &protocol);
  WARN(Report("Bandai protocol skeleton (17 joints)", protocol));
  CHECK(protocol.clips == 6);
  CHECK(protocol.max_error < 1e-3);

  // The files' own 22 joints (joint_Root at the floor, shoulders): read as the dataset does.
  RoundTrip source;
  int entry = 0;
  BvhOptions bvh;
  bvh.scale_to_metres = p.unit_scale;
  ForEachArchiveFile(
      data + "/bandai-1.tar.xz",
      [&](const std::string& name) {
        return name.size() > 4 && name.substr(name.size() - 4) == ".bvh" && entry++ % 40 == 0;
      },
      [&](const std::string& name, std::string_view bytes) {
        Measure(ReadBvhText(bytes, name, bvh), out, &source);
      });
  WARN(Report("Bandai source skeleton (22 joints)", source));
  CHECK(source.clips == 5);
  CHECK(source.max_error < 1e-3);
}

}  // namespace
}  // namespace motionfork
