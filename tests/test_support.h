// Helpers shared by the tests: synthetic fixtures built in code, temporary folders, and the
// real-data gate (skip without ../shared, fail under CI=true).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/motion.h"
#include "core/skeleton.h"

namespace motionfork::testing {

// A 17-joint humanoid laid out like the Bandai/H36M protocol skeletons (names as in Bandai).
inline std::shared_ptr<const Skeleton> MakeHumanoid() {
  SkeletonSpec s;
  s.name = "test_humanoid";
  s.joint_names = {"Hips",       "UpperLeg_R", "LowerLeg_R", "Foot_R", "UpperLeg_L",
                   "LowerLeg_L", "Foot_L",     "Spine",      "Chest",  "Neck",
                   "Head",       "UpperArm_L", "LowerArm_L", "Hand_L", "UpperArm_R",
                   "LowerArm_R", "Hand_R"};
  s.parent_names = {"",           "Hips",       "UpperLeg_R", "LowerLeg_R", "Hips",
                    "UpperLeg_L", "LowerLeg_L", "Hips",       "Spine",      "Chest",
                    "Neck",       "Chest",      "UpperArm_L", "LowerArm_L", "Chest",
                    "UpperArm_R", "LowerArm_R"};
  s.left_right = {{"UpperLeg_L", "UpperLeg_R"}, {"LowerLeg_L", "LowerLeg_R"}, {"Foot_L", "Foot_R"},
                  {"UpperArm_L", "UpperArm_R"}, {"LowerArm_L", "LowerArm_R"}, {"Hand_L", "Hand_R"}};
  PartitionSpec def{"default", {}};
  def.parts.push_back(PartSpec{"legs", {}, {"UpperLeg_R", "UpperLeg_L"}, false});
  def.parts.push_back(PartSpec{"upper", {}, {}, true});
  s.partitions = {def};
  return std::make_shared<const Skeleton>(Skeleton::Build(s));
}

// A T-frame motion of the humanoid: a rest pose (metres, Y up) plus smooth per-joint wobble and
// a root drifting forward, deterministic for a seed.
inline Motion MakeWalkingMotion(int frames, double fps = 30.0, unsigned seed = 7) {
  auto skel = MakeHumanoid();
  // Rest offsets from the parent, metres.
  // The knees bend forward (6 cm in front of the hip-ankle line), as people's do: the frame
  // detection (rig/body_frame.h) tells left from right by it.
  const float rest[17][3] = {{0, 0.95f, 0},       {-0.1f, 0, 0},     {0, -0.42f, 0.06f},
                             {0, -0.42f, -0.06f}, {0.1f, 0, 0},      {0, -0.42f, 0.06f},
                             {0, -0.42f, -0.06f}, {0, 0.2f, 0},      {0, 0.25f, 0},
                             {0, 0.15f, 0},       {0, 0.12f, 0.02f}, {0.18f, 0, 0},
                             {0.28f, 0, 0},       {0.25f, 0, 0},     {-0.18f, 0, 0},
                             {-0.28f, 0, 0},      {-0.25f, 0, 0}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> phase(0, 6.283f);
  float ph[17][3];
  for (auto& j : ph)
    for (float& a : j) a = phase(rng);
  std::vector<float> p(static_cast<size_t>(frames) * 17 * 3);
  for (int t = 0; t < frames; ++t) {
    const float time = static_cast<float>(t / fps);
    float* f = p.data() + static_cast<size_t>(t) * 51;
    for (int j = 0; j < 17; ++j) {
      const int par = skel->parent(j);
      for (int a = 0; a < 3; ++a) {
        float off = rest[j][a] + 0.05f * std::sin(2.0f * time + ph[j][a]);
        if (j == 0 && a == 2) off += 1.2f * time;  // walk forward along +Z
        f[3 * j + a] = (par >= 0 ? f[3 * par + a] : 0.0f) + off;
      }
    }
  }
  return Motion(skel, fps, std::move(p));
}

// A fresh, empty temporary directory, removed when the object goes away.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("motionfork_test_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// Names in dir of temporary files or folders a killed or failed write would leave behind
// ("*.tmp<digits>", io/file_util.h).
inline std::vector<std::string> TemporaryLeftovers(const std::filesystem::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.find(".tmp") != std::string::npos) found.push_back(name);
  }
  return found;
}

// A test that cannot run here and would skip: under CI=true (where every test must run) throws
// `why`, so the test fails; elsewhere returns and the caller skips (prints "SKIPPED: ...").
inline void FailUnderCi(const std::string& why) {
  const char* ci = std::getenv("CI");
  if (ci && std::string(ci) == "true") throw std::runtime_error("CI=true but " + why);
}

// Real data lives in ../shared. Returns its path, or "" when the test should skip (prints the
// reason as "SKIPPED: ..." so CTest reports a skip). Under CI=true a missing folder fails.
inline std::string SharedDataDir(const std::string& sub) {
  const std::filesystem::path dir = std::filesystem::path(MOTIONFORK_SHARED_DIR) / sub;
  if (std::filesystem::exists(dir)) return dir.string();
  FailUnderCi("the shared data folder " + dir.string() +
              " is missing; CI must run the real-data tests");
  return "";
}

#ifdef MOTIONFORK_BINARY_DIR
// The dataset cache real-data tests share: $MOTIONFORK_CACHE_DIR (scripts/test.sh sets it), else
// one under the build folder, since CTest runs every test case in its own process (the cache
// follows source changes).
inline std::string TestCacheDir() {
  const char* env = std::getenv("MOTIONFORK_CACHE_DIR");
  return env && *env && std::string(env) != "none"
             ? std::string(env)
             : std::string(MOTIONFORK_BINARY_DIR) + "/test-cache";
}
#endif

}  // namespace motionfork::testing
