// `motionfork check` and `motionfork constraints`, run as users run them.
#include <sys/wait.h>

#include <array>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fixtures.h"
#include "io/csv.h"
#include "test_support.h"

using namespace motionfork;
using namespace motionfork::testing;

namespace {

const std::string kBinary = std::string(MOTIONFORK_BINARY_DIR) + "/apps/motionfork/motionfork";

struct Run {
  int status = -1;
  std::string out;  // stdout only
  std::string err;
};

// Empty status -1 when the binary is not built (the test then skips).
Run Motionfork(const std::string& args, const TempDir& dir) {
  Run r;
  if (!std::filesystem::exists(kBinary)) return r;
  const std::string err_file = dir.file("stderr.txt");
  const std::string cmd = kBinary + " --quiet " + args + " 2>" + err_file;
  FILE* pipe = popen(cmd.c_str(), "r");
  REQUIRE(pipe);
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int st = pclose(pipe);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  std::ifstream e(err_file);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  return r;
}

bool BinaryMissing() {
  if (std::filesystem::exists(kBinary)) return false;
  if (const char* ci = std::getenv("CI"); ci && std::string(ci) == "true") {
    FAIL("CI=true but " << kBinary << " is not built");
  }
  WARN("SKIPPED: " << kBinary << " is not built");
  return true;
}

// A 10-frame H36M motion written as CSV with joint names; frames in `bent` get the left knee
// bent 50 degrees backwards.
std::string WriteH36m(const TempDir& dir, const std::string& name, const std::vector<int>& bent) {
  const auto s = ShippedSkeleton("h36m").skeleton;
  const Pose neutral = H36mNeutral(*s);
  const BodyAxes ax = Axes(*s, neutral, "LHip", "RHip", "Hips", "Thorax");
  std::vector<float> frames;
  for (int t = 0; t < 10; ++t) {
    Pose p = neutral;
    if (std::find(bent.begin(), bent.end(), t) != bent.end()) {
      Rotate(*s, &p, {"LFoot"}, At(*s, p, "LKnee"), ax.left, -50);
    }
    frames.insert(frames.end(), p.begin(), p.end());
  }
  const std::string path = dir.file(name);
  WriteCsvMotion(path, Motion(s, 50, frames));
  return path;
}

}  // namespace

TEST_CASE("check: exit status 0 when every frame is valid, 1 otherwise, 2 on bad input") {
  if (BinaryMissing()) return;
  TempDir dir;
  const std::string good = WriteH36m(dir, "good.csv", {});
  const std::string bad = WriteH36m(dir, "bad.csv", {3, 7});

  Run r = Motionfork("check " + good + " --constraints h36m", dir);
  INFO(r.out << r.err);
  CHECK(r.status == 0);
  CHECK(r.out.find("valid frames: 10 of 10") != std::string::npos);

  // The set is found from the joint names when not given.
  r = Motionfork("check " + bad, dir);
  CHECK(r.status == 1);
  CHECK(r.out.find("constraints:  h36m") != std::string::npos);
  CHECK(r.out.find("valid frames: 8 of 10") != std::string::npos);
  CHECK(r.out.find("Leg2ThighPlane_L") != std::string::npos);
  CHECK(r.out.find("frame 3") != std::string::npos);

  r = Motionfork("check " + bad + " --constraints h36m --json --angles " + dir.file("angles.csv"),
                 dir);
  CHECK(r.status == 1);
  for (const char* key : {"\"frames\": 10", "\"valid_frame_share\": 0.8", "\"violation_rate\": 0.2",
                          "\"name\": \"Leg2ThighPlane_L\"", "\"worst_frames\": [{\"frame\": "}) {
    INFO(key);
    CHECK(r.out.find(key) != std::string::npos);
  }
  std::ifstream angles(dir.file("angles.csv"));
  std::string header;
  std::getline(angles, header);
  CHECK(header.rfind("frame,time_s,Neck2Spine,HeadPlane2TorsoPlane,Leg2ThighPlane_L", 0) == 0);

  // Bad input: a malformed constraint file, an unknown set, a skeleton that does not fit.
  {
    std::ofstream f(dir.file("broken.yaml"));
    f << "name: broken\nconstraints:\n  - name: Knee\n    a: bone(LKnee, LFoot)\n    b: bone(LHip, "
         "LKnee)\n"
         "    range: [90, 10]\n";
  }
  r = Motionfork("check " + good + " --constraints " + dir.file("broken.yaml"), dir);
  CHECK(r.status == 2);
  CHECK(r.err.find("broken.yaml") != std::string::npos);
  CHECK(r.err.find("constraint 'Knee'") != std::string::npos);
  r = Motionfork("check " + good + " --constraints nosuchset", dir);
  CHECK(r.status == 2);
  CHECK(r.err.find("nosuchset") != std::string::npos);
  // Human3.6M's joints onto HumanEva's set: mapped by their roles, and said so.
  r = Motionfork("check " + good + " --constraints humaneva", dir);
  CHECK(r.status != 2);
  CHECK(r.err.find("joints read as the h36m rig onto skeleton 'humaneva'") != std::string::npos);
  r = Motionfork("check --help", dir);
  CHECK(r.status == 0);
  CHECK(r.out.find("Exit status") != std::string::npos);
}

TEST_CASE("constraints show and fit on the command line") {
  if (BinaryMissing()) return;
  TempDir dir;
  Run r = Motionfork("constraints show humaneva", dir);
  CHECK(r.status == 0);
  CHECK(r.out.find("Arm2ShoulderPlane_R  [0, 91] deg") != std::string::npos);

  const std::string data = SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: fit needs ../shared/data/bandai");
    return;
  }
  const char* env = std::getenv("MOTIONFORK_CACHE_DIR");
  const std::string cache =
      env && *env ? std::string(env) : std::string(MOTIONFORK_BINARY_DIR) + "/test-cache";
  const std::string out = dir.file("bandai_fitted.yaml");
  r = Motionfork(
      "--cache-dir " + cache + " constraints fit --protocol bandai --data " + data + " -o " + out,
      dir);
  INFO(r.out << r.err);
  REQUIRE(r.status == 0);
  CHECK(r.out.find("test split:") != std::string::npos);
  // Same file as the committed one apart from the header comment (which names its -o and data).
  auto body = [](const std::string& path) {
    std::ifstream f(path);
    std::string line, text;
    while (std::getline(f, line)) {
      if (line.rfind("#", 0) != 0) text += line + "\n";
    }
    return text;
  };
  CHECK(body(out) == body(std::string(MOTIONFORK_CONFIG_DIR) + "/constraints/bandai.yaml"));
  std::ifstream f(out);
  std::string first, second;
  std::getline(f, first);
  std::getline(f, second);
  CHECK(second.find("motionfork constraints fit --protocol bandai --data " + data + " -o " + out) !=
        std::string::npos);
}
