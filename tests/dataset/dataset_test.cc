// Dataset loading on synthetic data written in code: VideoPose3D-style manifests (H36M,
// HumanEva-I layouts) and Bandai-style BVH folders with a split file.
#include "dataset/dataset.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/windows.h"
#include "io/npy.h"
#include "test_support.h"

using namespace motionfork;
namespace fs = std::filesystem;

namespace {

ProtocolOptions Protocol(const std::string& name) {
  return LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", name));
}
SkeletonConfig SkeletonOf(const ProtocolOptions& p) {
  return LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", p.skeleton));
}

// Writes one take of J joints, T frames: joint j at (j, t/100, 0) metres.
void WriteTake(const fs::path& dir, std::ostream& manifest, const std::string& subject,
               const std::string& action, int T, int J, double fps) {
  NpyArray a;
  a.shape = {T, J, 3};
  a.data.resize(static_cast<size_t>(T) * J * 3);
  for (int t = 0; t < T; ++t)
    for (int j = 0; j < J; ++j) {
      float* p = &a.data[(static_cast<size_t>(t) * J + j) * 3];
      p[0] = 0.1f * j;
      p[1] = 0.01f * t;
      p[2] = 0.05f * (j % 3);
    }
  const std::string rel = subject + "/" + action + ".npy";
  fs::create_directories(dir / subject);
  WriteNpy((dir / rel).string(), a);
  manifest << subject << '\t' << action << '\t' << T << '\t' << J << '\t' << fps << '\t' << rel
           << '\n';
}

}  // namespace

TEST_CASE("h36m protocol on a synthetic VideoPose3D export: split, joints, windows") {
  testing::TempDir dir;
  std::ofstream manifest(dir.file("manifest.tsv"));
  manifest << "subject\taction\tframes\tjoints\tfps\tfile\n";
  const std::vector<std::string> subjects = {"S1", "S5", "S6", "S7", "S8", "S9", "S11", "S2"};
  int expect_test_windows = 0, expect_train_clips = 0;
  for (size_t s = 0; s < subjects.size(); ++s) {
    for (int a = 0; a < 3; ++a) {
      const int T = 100 + 37 * static_cast<int>(s) + 50 * a;  // some shorter than 125
      WriteTake(dir.path(), manifest, subjects[s], "Walking " + std::to_string(a), T, 32, 50);
      const bool test = subjects[s] == "S9" || subjects[s] == "S11";
      if (test && T >= 125) {
        for (int i = 0; i < T - 125; i += 25) ++expect_test_windows;
      }
      if (!test && subjects[s] != "S2" && T >= 125) ++expect_train_clips;
    }
  }
  manifest.close();
  const ProtocolOptions p = Protocol("h36m");
  const Dataset ds = LoadDataset(p, SkeletonOf(p), dir.path().string());
  CHECK(ds.ClipIndices(Split::kTrain).size() == static_cast<size_t>(expect_train_clips));
  const auto test = ds.ClipIndices(Split::kTest);
  const auto windows =
      SlidingWindows(ds.ClipFrames(test), p.window_length(), p.test_stride, p.test_include_last);
  CHECK(windows.size() == static_cast<size_t>(expect_test_windows));
  for (const Clip& c : ds.clips) {
    REQUIRE(c.motion.num_joints() == 17);
    CHECK(c.motion.fps() == 50);
    CHECK(c.subject != "S2");
    // Kept joint 14 is source joint 25 (R shoulder): x = 2.5 m in the synthetic layout.
    CHECK(c.motion.at(0, 14)[0] == Approx(2.5));
  }
  int not_split = 0;
  for (const SkippedClip& s : ds.skipped) not_split += s.reason == "subject not in the split";
  CHECK(not_split == 3);
}

TEST_CASE("humaneva protocol drops the three bad takes and short sequences") {
  testing::TempDir dir;
  std::ofstream manifest(dir.file("manifest.tsv"));
  manifest << "subject\taction\tframes\tjoints\tfps\tfile\n";
  for (const char* s :
       {"Train/S1", "Train/S2", "Train/S3", "Validate/S1", "Validate/S2", "Validate/S3"}) {
    for (int c = 0; c < 5; ++c) {
      WriteTake(dir.path(), manifest, s, "Walking 1 chunk" + std::to_string(c), 70 + 10 * c, 15,
                60);
    }
  }
  manifest.close();
  const ProtocolOptions p = Protocol("humaneva");
  const Dataset ds = LoadDataset(p, SkeletonOf(p), dir.path().string());
  int dropped = 0, short_ones = 0;
  for (const SkippedClip& s : ds.skipped) {
    dropped += s.reason == "dropped take";
    short_ones += s.reason.rfind("shorter than 75", 0) == 0;
  }
  CHECK(dropped == 3);
  CHECK(short_ones ==
        5);  // chunk0 (70 frames) of every subject but Train/S3, whose chunk0 is dropped
  CHECK(ds.clips.size() == 30 - 3 - 5);
  for (const Clip& c : ds.clips) {
    CHECK_FALSE((c.subject == "Train/S3" &&
                 (c.action == "Walking 1 chunk0" || c.action == "Walking 1 chunk2")));
    CHECK_FALSE((c.subject == "Validate/S3" && c.action == "Walking 1 chunk4"));
  }
}

namespace {
// A Bandai-like BVH: the 22 Bandai joints, 6 channels each, identity rotations, the given
// number of frames; joint_Root translates along Z with time.
std::string BandaiLikeBvh(int frames) {
  const std::vector<std::pair<std::string, std::string>> joints = {{"joint_Root", ""},
                                                                   {"Hips", "joint_Root"},
                                                                   {"Spine", "Hips"},
                                                                   {"Chest", "Spine"},
                                                                   {"Neck", "Chest"},
                                                                   {"Head", "Neck"},
                                                                   {"Shoulder_L", "Chest"},
                                                                   {"UpperArm_L", "Shoulder_L"},
                                                                   {"LowerArm_L", "UpperArm_L"},
                                                                   {"Hand_L", "LowerArm_L"},
                                                                   {"Shoulder_R", "Chest"},
                                                                   {"UpperArm_R", "Shoulder_R"},
                                                                   {"LowerArm_R", "UpperArm_R"},
                                                                   {"Hand_R", "LowerArm_R"},
                                                                   {"UpperLeg_L", "Hips"},
                                                                   {"LowerLeg_L", "UpperLeg_L"},
                                                                   {"Foot_L", "LowerLeg_L"},
                                                                   {"Toes_L", "Foot_L"},
                                                                   {"UpperLeg_R", "Hips"},
                                                                   {"LowerLeg_R", "UpperLeg_R"},
                                                                   {"Foot_R", "LowerLeg_R"},
                                                                   {"Toes_R", "Foot_R"}};
  std::ostringstream s;
  s << "HIERARCHY\n";
  std::function<void(int, int)> emit = [&](int j, int depth) {
    const std::string pad(depth * 2, ' ');
    s << pad << (j == 0 ? "ROOT " : "JOINT ") << joints[j].first << "\n" << pad << "{\n";
    s << pad << "  OFFSET " << (j == 0 ? 0 : 10) << " " << (j == 0 ? 0 : 5) << " 0\n";
    s << pad << "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n";
    bool child = false;
    for (size_t k = 0; k < joints.size(); ++k) {
      if (joints[k].second == joints[j].first) {
        emit(static_cast<int>(k), depth + 1);
        child = true;
      }
    }
    if (!child)
      s << pad << "  End Site\n" << pad << "  {\n" << pad << "    OFFSET 0 1 0\n" << pad << "  }\n";
    s << pad << "}\n";
  };
  emit(0, 0);
  s << "MOTION\nFrames: " << frames << "\nFrame Time: 0.0333333\n";
  for (int t = 0; t < frames; ++t) {
    for (size_t j = 0; j < joints.size(); ++j) {
      s << (j ? " " : "") << (j == 0 ? 0 : 10) << " " << (j == 0 ? 0 : 5) << " " << (j == 0 ? t : 0)
        << " 0 0 0";
    }
    s << "\n";
  }
  return s.str();
}
}  // namespace

TEST_CASE("bandai protocol on a synthetic BVH folder: split file, labels, min length, cache") {
  testing::TempDir dir, cache;
  fs::create_directories(dir.path() / "pack");
  const std::vector<std::pair<std::string, int>> clips = {
      {"dataset-2_walk_normal_001", 100},
      {"dataset-2_run_elderly_002", 80},
      {"dataset-2_walk-turn-left_active_003", 60},
      {"dataset-1_bow_happy_004", 75},
      {"dataset-2_walk_normal_099", 90}};
  for (const auto& [name, frames] : clips) {
    std::ofstream((dir.path() / "pack" / (name + ".bvh")).string()) << BandaiLikeBvh(frames);
  }
  std::ofstream(dir.file("split.tsv"))
      << "# "
         "split\tclip\ntrain\tdataset-2_walk_normal_001.bvh\ntest\tdataset-2_run_elderly_002.bvh\n"
         "train\tdataset-2_walk-turn-left_active_003.bvh\ntrain\tdataset-1_bow_happy_004.bvh\n"
         "test\tdataset-2_missing_elderly_005.bvh\n";
  const ProtocolOptions p = Protocol("bandai");
  DatasetLoadOptions opts;
  opts.cache_dir = cache.path().string();
  const Dataset first = LoadDataset(p, SkeletonOf(p), dir.path().string(), opts);
  CHECK_FALSE(first.from_cache);
  REQUIRE(first.clips.size() == 3);
  CHECK(first.groups == std::vector<std::pair<std::string, int>>{{"pack", 5}});
  CHECK(first.split_missing == std::vector<std::string>{"dataset-2_missing_elderly_005"});
  const Clip& c0 = first.clips[0];
  CHECK(c0.name == "dataset-1_bow_happy_004");
  CHECK(c0.action == "bow");
  CHECK(c0.subject == "happy");
  CHECK(c0.motion.num_joints() == 17);
  CHECK(c0.motion.fps() == 30);
  // Frame 10: joint_Root moved 10 cm along Z; Hips sits 10 cm, 5 cm above it: metres.
  CHECK(c0.motion.at(10, 0)[0] == Approx(0.1));
  CHECK(c0.motion.at(10, 0)[1] == Approx(0.05));
  CHECK(c0.motion.at(10, 0)[2] == Approx(0.1));
  int short_ones = 0, unsplit = 0;
  for (const SkippedClip& s : first.skipped) {
    short_ones += s.reason == "shorter than 75 frames";
    unsplit += s.reason == "not in the split file";
  }
  CHECK(short_ones == 1);
  CHECK(unsplit == 1);

  const Dataset second = LoadDataset(p, SkeletonOf(p), dir.path().string(), opts);
  CHECK(second.from_cache);
  REQUIRE(second.clips.size() == first.clips.size());
  for (size_t i = 0; i < first.clips.size(); ++i) {
    CHECK(second.clips[i].name == first.clips[i].name);
    CHECK(second.clips[i].motion.positions() == first.clips[i].motion.positions());
  }
  // Touching a source file invalidates the cache.
  std::ofstream((dir.path() / "pack" / "dataset-2_walk_normal_099.bvh").string())
      << BandaiLikeBvh(91);
  CHECK_FALSE(LoadDataset(p, SkeletonOf(p), dir.path().string(), opts).from_cache);
}

TEST_CASE("dataset loading explains empty or wrong data folders") {
  testing::TempDir dir;
  const ProtocolOptions b = Protocol("bandai");
  CHECK_THROWS_WITH(LoadDataset(b, SkeletonOf(b), dir.path().string()),
                    Catch::Contains("no .bvh files"));
  const ProtocolOptions h = Protocol("h36m");
  CHECK_THROWS_WITH(
      LoadDataset(h, SkeletonOf(h), dir.path().string()),
      Catch::Contains("manifest.tsv") && Catch::Contains("videopose3d_to_motionfork.py"));
  CHECK_THROWS_WITH(LoadDataset(h, SkeletonOf(h), dir.file("nope")),
                    Catch::Contains("does not exist"));
}
