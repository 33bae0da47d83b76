// The Bandai protocol on the real data in ../shared/data/bandai (read from the archives in place).
#include <catch2/catch.hpp>
#include <chrono>

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "test_support.h"

using namespace motionfork;

TEST_CASE("bandai real data: 174 + 2,549 clips, 2,409 train / 314 test, cache round trip") {
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  testing::TempDir cache;
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", "bandai"));
  const SkeletonConfig s =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", p.skeleton));
  DatasetLoadOptions opts;
  opts.cache_dir = cache.path().string();
  const Dataset ds = LoadDataset(p, s, data, opts);
  REQUIRE(ds.groups.size() == 2);
  CHECK(ds.groups[0] == std::make_pair(std::string("bandai-1.tar.xz"), 174));
  CHECK(ds.groups[1] == std::make_pair(std::string("bandai-2.tar.xz"), 2549));
  CHECK(ds.split_missing.empty());
  int listed[2] = {0, 0}, short_clips = 0, other = 0;
  for (const Clip& c : ds.clips) listed[c.split == Split::kTrain ? 0 : 1]++;
  for (const SkippedClip& c : ds.skipped) {
    if (c.split == "train") listed[0]++;
    if (c.split == "test") listed[1]++;
    if (c.reason == "shorter than 75 frames") {
      ++short_clips;
      CHECK(c.frames < 75);
    } else {
      ++other;
    }
  }
  CHECK(listed[0] == 2409);
  CHECK(listed[1] == 314);
  CHECK(other == 0);
  for (const Clip& c : ds.clips) {
    CHECK(c.motion.num_frames() >= 75);
    if (c.split == Split::kTest) CHECK(c.subject == "elderly");
  }
  // Body size: the Head joint (base of the skull) sits 1.0-1.9 m above the lower ankle (Foot joint)
  // in the first frame of most clips.
  int plausible = 0;
  for (const Clip& c : ds.clips) {
    const float head = c.motion.at(0, 10)[1];
    const float foot = std::min(c.motion.at(0, 3)[1], c.motion.at(0, 6)[1]);
    plausible += head - foot > 1.0f && head - foot < 1.9f;
  }
  CHECK(plausible > 0.95 * ds.clips.size());

  const auto t0 = std::chrono::steady_clock::now();
  const Dataset again = LoadDataset(p, s, data, opts);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(again.from_cache);
  REQUIRE(again.clips.size() == ds.clips.size());
  for (size_t i = 0; i < ds.clips.size(); i += 97) {
    CHECK(again.clips[i].motion.positions() == ds.clips[i].motion.positions());
  }
  WARN("cold load " << ds.seconds_reading << " s, cached load " << seconds << " s, "
                    << ds.clips.size() << " usable clips, " << short_clips
                    << " shorter than 75 frames");
}
