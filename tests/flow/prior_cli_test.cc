// motionfork prior train|score|sample, run as users run them: help, outputs, exit statuses and
// messages for bad input, Ctrl-C and resume.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <catch2/catch.hpp>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bundle/prior_bundle.h"
#include "core/limbs.h"
#include "flow/pose_prior.h"
#include "io/csv.h"
#include "io/file_util.h"
#include "io/npy.h"
#include "run_motionfork.h"
#include "test_support.h"

extern char** environ;

using namespace motionfork;

namespace {

std::string Binary() { return std::string(MOTIONFORK_BINARY_DIR) + "/apps/motionfork/motionfork"; }

// "" when the binary is there; else the reason to skip (under CI=true: a failure).
std::string MissingBinary() {
  if (std::filesystem::exists(Binary())) return "";
  const char* ci = std::getenv("CI");
  if (ci && std::string(ci) == "true") FAIL("CI=true but " << Binary() << " was not built");
  return "SKIPPED: " + Binary() + " not built (build the motionfork target first)";
}

using testing::Run;

Run Motionfork(const std::string& args) { return testing::RunMotionfork(Binary(), args); }

// Runs the command and sends SIGINT when a line of its output contains `trigger`.
Run MotionforkInterrupted(const std::vector<std::string>& args, const std::string& trigger) {
  int fds[2];
  REQUIRE(pipe(fds) == 0);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  std::vector<std::string> all = {Binary()};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid;
  REQUIRE(posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) == 0);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  FILE* out = fdopen(fds[0], "r");
  Run r{0, ""};
  char* line = nullptr;
  size_t cap = 0;
  bool sent = false;
  while (getline(&line, &cap, out) > 0) {
    r.output += line;
    if (!sent && r.output.find(trigger) != std::string::npos) {
      kill(pid, SIGINT);
      sent = true;
    }
  }
  free(line);
  fclose(out);
  int st = 0;
  waitpid(pid, &st, 0);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// An untrained bundle on the test humanoid (Bandai joint names), mapped through 'bandai'.
void WriteBundle(const std::string& dir, std::shared_ptr<const Skeleton> skeleton,
                 const std::string& config) {
  PriorConfig c;
  PosePrior prior(std::move(skeleton), c);
  prior.set_skeleton_config(config);
  SavePosePrior(prior, dir);
}

}  // namespace

TEST_CASE("prior subcommands have --help") {
  if (const std::string why = MissingBinary(); !why.empty()) {
    WARN(why);
    return;
  }
  for (const char* sub : {"prior", "prior train", "prior score", "prior sample"}) {
    const Run r = Motionfork(std::string(sub) + " --help");
    INFO(sub << ": " << r.output);
    CHECK(r.status == 0);
    CHECK(r.output.find("Usage") != std::string::npos);
  }
}

TEST_CASE("prior score and sample: outputs, and exit 2 with a clear message for bad input") {
  if (const std::string why = MissingBinary(); !why.empty()) {
    WARN(why);
    return;
  }
  testing::TempDir dir;
  const std::string model = dir.file("prior");
  WriteBundle(model, testing::MakeHumanoid(), "bandai");
  const Motion walk = testing::MakeWalkingMotion(20);
  WriteCsvMotion(dir.file("walk.csv"), walk);

  Run r = Motionfork("prior score " + dir.file("walk.csv") + " --model " + model);
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(r.output.find("    19 ") != std::string::npos);  // one line per frame
  CHECK(r.output.find("mean") != std::string::npos);
  r = Motionfork("prior score " + dir.file("walk.csv") + " --model " + model + " --json");
  CHECK(r.status == 0);
  CHECK(r.output.find("\"frames\": 20") != std::string::npos);
  CHECK(r.output.find("\"nll\": [") != std::string::npos);
  CHECK(r.output.find("\"worst_frame\"") != std::string::npos);
  // .npy stores no joint names: bound by index.
  WriteNpyMotion(dir.file("walk.npy"), walk);
  CHECK(Motionfork("prior score " + dir.file("walk.npy") + " --model " + model).status == 0);

  // Wrong joint count.
  NpyArray five{{4, 5, 3}, std::vector<float>(60, 0.1f)};
  for (size_t i = 0; i < five.data.size(); ++i) five.data[i] = 0.1f * static_cast<float>(i);
  WriteNpy(dir.file("five.npy"), five);
  r = Motionfork("prior score " + dir.file("five.npy") + " --model " + model);
  CHECK(r.status == 2);
  CHECK(r.output.find("expected 17 joints, got 5") != std::string::npos);
  // NaN in the file.
  std::string csv = ReadFileBytes(dir.file("walk.csv"));
  const size_t at = csv.find('\n', csv.find("Hips.x")) + 1;
  csv.replace(at, csv.find(',', at) - at, "nan");
  WriteFileAtomically(dir.file("nan.csv"), csv);
  r = Motionfork("prior score " + dir.file("nan.csv") + " --model " + model);
  CHECK(r.status == 2);
  CHECK(r.output.find("finite") != std::string::npos);
  // A zero-length bone (frame 3: the right knee on the right hip).
  std::vector<float> p = walk.positions();
  for (int a = 0; a < 3; ++a) p[(3 * 17 + 2) * 3 + a] = p[(3 * 17 + 1) * 3 + a];
  WriteCsvMotion(dir.file("collapsed.csv"), Motion(walk.skeleton_ptr(), 30.0, p));
  r = Motionfork("prior score " + dir.file("collapsed.csv") + " --model " + model);
  CHECK(r.status == 2);
  CHECK(r.output.find("frame 3") != std::string::npos);
  CHECK(r.output.find("zero-length") != std::string::npos);
  // A bundle from another skeleton (H36M joint names) than the motion's.
  std::vector<std::string> h36m = {"Hips",   "RHip",   "RKnee",     "RFoot",  "LHip",  "LKnee",
                                   "LFoot",  "Spine",  "Thorax",    "Neck",   "Head",  "LShoulder",
                                   "LElbow", "LWrist", "RShoulder", "RElbow", "RWrist"};
  WriteBundle(dir.file("h36m_prior"),
              std::make_shared<const Skeleton>(
                  Skeleton::FromParents("h36m", h36m, walk.skeleton().parents())),
              "h36m");
  // Its joints' roles are known (configs/rigs/h36m.yaml): the motion is mapped onto them.
  r = Motionfork("prior score " + dir.file("walk.csv") + " --model " + dir.file("h36m_prior") +
                 " 2>&1");
  CHECK(r.status == 0);
  CHECK(r.output.find("joints read as the bandai rig onto skeleton 'h36m'") != std::string::npos);
  // A prior whose joints no rig convention names: refused, naming it.
  std::vector<std::string> odd;
  for (int j = 0; j < 17; ++j) odd.push_back("bone" + std::to_string(j));
  WriteBundle(dir.file("odd_prior"),
              std::make_shared<const Skeleton>(
                  Skeleton::FromParents("odd", odd, walk.skeleton().parents())),
              "odd");
  r = Motionfork("prior score " + dir.file("walk.csv") + " --model " + dir.file("odd_prior"));
  CHECK(r.status == 2);
  CHECK(r.output.find("expects poses of skeleton 'odd'") != std::string::npos);
  // Not a bundle.
  r = Motionfork("prior score " + dir.file("walk.csv") + " --model " + dir.path().string());
  CHECK(r.status == 2);
  CHECK(r.output.find("prior.yaml") != std::string::npos);

  r = Motionfork("prior sample --model " + model + " -n 7 -o " + dir.file("s.npy") + " --seed 3");
  CHECK(r.status == 0);
  CHECK(ReadNpy(dir.file("s.npy")).shape == std::vector<int64_t>{7, 17, 3});
  CHECK(Motionfork("prior sample --model " + model + " -n 7 -o " + dir.file("s.csv")).status == 0);
  r = Motionfork("prior sample --model " + model + " -n 7 -o " + dir.file("s.txt"));
  CHECK(r.status == 2);
  CHECK(r.output.find(".txt") != std::string::npos);
  CHECK(Motionfork("prior sample --model " + model + " -n 0 -o " + dir.file("s.npy")).status == 2);
}

TEST_CASE(
    "prior train on Bandai: bundle and log, refuses to overwrite, Ctrl-C then resume equals one "
    "run") {
  if (const std::string why = MissingBinary(); !why.empty()) {
    WARN(why);
    return;
  }
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  testing::TempDir dir;
  const std::string cache = std::string(MOTIONFORK_BINARY_DIR) + "/test_cache";
  WriteFileAtomically(dir.file("tiny.yaml"),
                      "training:\n  epochs: 40\n  constant_epochs: 10\n  batch_size: 1024\n"
                      "  frame_stride: 40\n  learning_rate: 3.0e-3\n  min_steps: 0\n");
  const std::string common = "--cache-dir " + cache + " prior train --protocol bandai --data " +
                             data + " --config " + dir.file("tiny.yaml") + " --out ";
  auto run = [&](const std::string& out, const std::string& extra = "") {
    return testing::RunShell(Binary() + " " + common + out + extra + " 2>&1");
  };
  Run r = run(dir.file("a"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("epoch 40/40") != std::string::npos);
  CHECK(r.output.find("held-out NLL") != std::string::npos);
  CHECK(std::filesystem::exists(dir.file("a/prior.yaml")));
  CHECK(std::filesystem::exists(dir.file("a/weights.npy")));
  CHECK_FALSE(std::filesystem::exists(dir.file("a/checkpoint.pt")));
  const std::string log = ReadFileBytes(dir.file("a/train_log.tsv"));
  CHECK(std::count(log.begin(), log.end(), '\n') == 41);
  const PosePrior trained = LoadPosePrior(dir.file("a"));
  CHECK(trained.summary().epochs_completed == 40);
  CHECK(trained.summary().protocol == "bandai");
  CHECK(trained.skeleton_config() == "bandai");

  // A finished run is not silently overwritten.
  r = run(dir.file("a"));
  CHECK(r.status == 2);
  CHECK(r.output.find("--restart") != std::string::npos);

  // Ctrl-C after the first epoch: exit 130, a checkpoint; the same command resumes; the result
  // equals the uninterrupted run's weights byte for byte.
  const std::string b = dir.file("b");
  std::vector<std::string> args = {
      "--cache-dir", cache,    "prior", "train",    "--protocol",
      "bandai",      "--data", data,    "--config", dir.file("tiny.yaml"),
      "--out",       b};
  r = MotionforkInterrupted(args, "epoch  1/40");
  INFO(r.output);
  CHECK(r.status == 130);
  CHECK(r.output.find("interrupted") != std::string::npos);
  CHECK(std::filesystem::exists(b + "/checkpoint.pt"));
  CHECK_FALSE(std::filesystem::exists(b + "/prior.yaml"));
  r = run(b);
  CHECK(r.status == 0);
  CHECK(r.output.find("resuming:") != std::string::npos);
  CHECK(ReadFileBytes(b + "/weights.npy") == ReadFileBytes(dir.file("a/weights.npy")));

  // --restart trains again; a config error names the file and the key.
  CHECK(run(dir.file("a"), " --restart").status == 0);
  WriteFileAtomically(dir.file("bad.yaml"), "training:\n  epoch: 3\n");
  r = Motionfork("prior train --protocol bandai --data " + data + " --config " +
                 dir.file("bad.yaml") + " --out " + dir.file("c"));
  CHECK(r.status == 2);
  CHECK(r.output.find("bad.yaml:line 2") != std::string::npos);
  CHECK(r.output.find("training.epoch") != std::string::npos);
}
