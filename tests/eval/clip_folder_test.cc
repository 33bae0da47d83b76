// `motionfork eval --clips DIR`: a folder of a user's own files read under a protocol's settings.
#include "eval/clip_folder.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "eval/test_set.h"
#include "io/motion_file.h"
#include "test_support.h"

using namespace motionfork;

TEST_CASE("a folder of CSV and NumPy files becomes test clips on the protocol skeleton and rate") {
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", "bandai"));
  const SkeletonConfig s =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", p.skeleton));
  testing::TempDir dir;
  std::filesystem::create_directories(dir.path() / "takes");
  // 200 frames at 60 Hz -> 100 frames at 30 Hz; named like a Bandai clip, so labelled.
  WriteMotionFile(dir.file("takes/dataset-9_kick_mine_001.csv"),
                  testing::MakeWalkingMotion(200, 60));
  // 80 frames at 30 Hz as .npy (no names, no rate: bound by joint count, protocol fps assumed).
  WriteMotionFile(dir.file("b.npy"), testing::MakeWalkingMotion(80, 30, 2));
  // Too short for one 75-frame window.
  WriteMotionFile(dir.file("short.csv"), testing::MakeWalkingMotion(50, 30));
  std::ofstream(dir.file("notes.txt")) << "not a motion";

  const ClipFolder f = LoadClipFolder(p, s, dir.path().string());
  REQUIRE(f.clips.size() == 2);
  CHECK(f.clips[0].name == "b");
  CHECK(f.clips[0].motion.num_frames() == 80);
  CHECK(f.clips[1].name == "dataset-9_kick_mine_001");
  CHECK(f.clips[1].group == "takes");
  CHECK(f.clips[1].action == "kick");
  CHECK(f.clips[1].subject == "mine");
  CHECK(f.clips[1].motion.fps() == 30);
  CHECK(f.clips[1].motion.num_frames() == 100);
  CHECK(f.clips[1].motion.skeleton().SameStructure(*s.skeleton));
  REQUIRE(f.skipped.size() == 1);
  CHECK(f.skipped[0].name == "short");
  CHECK(f.skipped[0].reason == "shorter than 75 frames");

  std::vector<const Clip*> clips = {&f.clips[0], &f.clips[1]};
  const TestSet ts = BuildTestSet(clips, p);
  CHECK(ts.num_windows() == 1 + 2);  // 80 frames: start 0; 100 frames: starts 0, 15

  testing::TempDir empty;
  std::ofstream(empty.file("readme.md")) << "nothing";
  CHECK_THROWS_WITH(LoadClipFolder(p, s, empty.path().string()), Catch::Contains("no motion file"));
  CHECK_THROWS_WITH(LoadClipFolder(p, s, empty.file("missing")), Catch::Contains("does not exist"));
  // A file whose joints do not fit the skeleton names the file.
  WriteMotionFile(empty.file("odd.npy"),
                  Motion(std::make_shared<const Skeleton>(Skeleton::Anonymous(5)), 30,
                         std::vector<float>(5 * 3 * 80, 0.0f)));
  CHECK_THROWS_WITH(LoadClipFolder(p, s, empty.path().string()), Catch::Contains("odd.npy"));
}
