// Data-parallel training as users run it: `--nproc-per-node`, `--nnodes` (two "nodes" on this
// machine over TCP on localhost), a killed worker, a resumed run with fewer workers, and the
// errors of a bad run environment. The data folder is made here (synthetic walks, as
// train_cli_test.cc does).
#include <signal.h>
#include <torch/torch.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "io/file_util.h"
#include "launch/worker_launcher.h"
#include "run_motionfork.h"
#include "test_support.h"

using Catch::Contains;
using motionfork::ReadFileBytes;
using motionfork::testing::Motionfork;
using motionfork::testing::Run;
using motionfork::testing::RunShell;

namespace {

namespace fs = std::filesystem;

// A tiny generator config: `bn` batch norm, `epochs` epochs of `windows` windows in batches of 4.
std::string TinyConfig(bool bn, int epochs, int windows, int seed = 0) {
  return std::string(R"(name: tiny-dist
protocol: bandai
generator:
  n_pre: 4
  hidden: 16
  blocks: 1
  nz: 4
  batch_norm: )") +
         (bn ? "true" : "false") + R"(
  partition: default
losses:
  past_reconstruction: 100
  limb_length: 500
  diversity: [5, 10]
  diversity_scale: [15, 50]
  best_of_many: 2
  multimodal: 1
multimodal:
  last_pose_threshold: 0.05
  future_min_distance: 0.1
  max_per_window: 4
training:
  samples_per_part: [2, 2]
  batch_histories: 4
  epochs: )" +
         std::to_string(epochs) +
         R"(
  windows_per_epoch: )" +
         std::to_string(windows) + R"(
  lr_constant_epochs: 1
  learning_rate: 0.001
  grad_clip: 100
  window_stride: 10
  seed: )" +
         std::to_string(seed) +
         R"(
  threads: 1
)";
}

struct Fixture {
  motionfork::testing::TempDir dir;
  std::string data = dir.file("data");
  Fixture() {
    fs::create_directories(data);
    int heading = 0;
    for (const char* clip : {"walk_a", "walk_b", "walk_c"}) {
      const Run r = Motionfork("synth walk --frames 160 --heading " +
                               std::to_string(heading += 40) + " -o " + data + "/" + clip + ".bvh");
      REQUIRE(r.status == 0);
    }
    std::ofstream(data + "/split.tsv")
        << "train\twalk_a.bvh\ntrain\twalk_b.bvh\ntest\twalk_c.bvh\n";
  }
  std::string Config(const std::string& name, const std::string& text) const {
    std::ofstream(dir.file(name)) << text;
    return dir.file(name);
  }
  std::string Train(const std::string& config, const std::string& out) const {
    return "-q train --config " + config + " --data " + data + " --out " + out;
  }
};

// Every tensor of a LibTorch archive (a bundle's generator.pt), by its dotted name.
void CollectWeights(torch::serialize::InputArchive& archive, const std::string& prefix,
                    std::map<std::string, torch::Tensor>* out) {
  for (const std::string& key : archive.keys()) {
    torch::Tensor t;
    torch::serialize::InputArchive sub;
    if (archive.try_read(key, t)) {
      (*out)[prefix + key] = t;
    } else if (archive.try_read(key, sub)) {
      CollectWeights(sub, prefix + key + ".", out);
    }
  }
}

std::map<std::string, torch::Tensor> Weights(const std::string& file) {
  torch::serialize::InputArchive archive;
  archive.load_from(file);
  std::map<std::string, torch::Tensor> out;
  CollectWeights(archive, "", &out);
  return out;
}

// The total loss of every epoch in a training log (OUT/log.csv, the column "total").
std::vector<double> LossCurve(const std::string& log) {
  std::ifstream in(log);
  std::string line;
  std::getline(in, line);
  int column = 0;
  for (size_t p = 0; p < line.find("total"); ++p) column += line[p] == ',';
  std::vector<double> out;
  while (std::getline(in, line)) {
    size_t p = 0;
    for (int c = 0; c < column; ++c) p = line.find(',', p) + 1;
    out.push_back(std::stod(line.substr(p)));
  }
  return out;
}

// The pid of the worker of `rank` whose command line names `marker` (0 when there is none).
pid_t WorkerPid(int rank, const std::string& marker) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    // /proc's files report no size: read them as streams.
    auto read = [&](const char* file) {
      std::ifstream in(entry.path() / file, std::ios::binary);
      return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const std::string cmdline = read("cmdline"), environ = read("environ");
    if (cmdline.find(marker) == std::string::npos) continue;
    if (environ.find(std::string("\0RANK=", 6) + std::to_string(rank) + '\0') != std::string::npos)
      return std::stoi(name);
  }
  return 0;
}

int Rows(const std::string& log) {
  std::ifstream in(log);
  int rows = -1;  // the header
  for (std::string line; std::getline(in, line);) rows += !line.empty();
  return std::max(rows, 0);
}

// Trains `config` on one worker and on two (`extra` added to the two-worker command line); returns
// the largest difference between the two bundles' tensors.
double LargestWeightDifference(const Fixture& f, const std::string& config,
                               const std::string& extra = "") {
  const std::string one_dir = f.dir.file("one"), two_dir = f.dir.file("two");
  fs::remove_all(one_dir);
  fs::remove_all(two_dir);
  Run one = Motionfork(f.Train(config, one_dir));
  INFO(one.output);
  REQUIRE(one.status == 0);
  Run two = Motionfork(f.Train(config, two_dir) + " --nproc-per-node 2" + extra);
  INFO(two.output);
  REQUIRE(two.status == 0);
  CHECK_THAT(two.output, Contains("starting 2 workers (ranks 0..1 of 2"));
  // Rank 0 alone wrote: one log with one row per epoch.
  CHECK(Rows(two_dir + "/log.csv") == Rows(one_dir + "/log.csv"));
  const auto a = Weights(one_dir + "/generator.pt");
  const auto b = Weights(two_dir + "/generator.pt");
  REQUIRE(a.size() > 4);
  REQUIRE(a.size() == b.size());
  double largest = 0;
  for (const auto& [name, t] : a) {
    REQUIRE(b.count(name));
    largest = std::max(largest, (t - b.at(name)).abs().max().item<double>());
  }
  return largest;
}

}  // namespace

TEST_CASE("two workers at half the batch each end with one worker's weights at the full batch") {
  Fixture f;
  // No batch norm: each worker's share then computes exactly what its rows of the whole batch do.
  const double largest =
      LargestWeightDifference(f, f.Config("tiny.yaml", TinyConfig(false, 1, 20)));
  CHECK(largest < 1e-5);
  CHECK(largest > 0);  // sums in another order: two real runs, not one file twice
}

TEST_CASE("with synchronised batch norm two workers end with one worker's weights") {
  Fixture f;
  // Batch norm over every worker's share (training.sync_batch_norm, the default): the same steps
  // as one worker on the whole batch, running statistics included (they are in the bundle).
  const std::string config = f.Config("tiny.yaml", TinyConfig(true, 1, 20));  // 5 steps
  const double synced = LargestWeightDifference(f, config);
  CHECK(synced < 1e-5);
  CHECK(synced > 0);
  // Each worker normalising its own share (sync_batch_norm: false) takes other steps.
  std::string own = TinyConfig(true, 1, 20);
  own.insert(own.find("  threads: 1"), "  sync_batch_norm: false\n");
  const double per_worker = LargestWeightDifference(f, f.Config("own.yaml", own));
  INFO("synchronised: " << synced << ", per worker: " << per_worker);
  CHECK(per_worker > 100 * synced);
}

TEST_CASE("with every augmentation two workers still end with one worker's weights") {
  Fixture f;
  // Every worker draws the whole step's variations (mirror, size, speed) and each window's history
  // noise comes from its place in the step: the shares are the rows of one worker's batch.
  std::string varied = TinyConfig(false, 1, 20);
  varied += "augmentation:\n  mirror: 0.5\n  scale: 1.1\n  speed: 1.3\n  history_noise: 0.01\n";
  const double largest = LargestWeightDifference(f, f.Config("varied.yaml", varied));
  CHECK(largest < 1e-5);
  CHECK(largest > 0);
}

TEST_CASE("with batch norm, two workers' loss curve stays within one worker's seed spread") {
  Fixture f;
  std::vector<std::vector<double>> seeds;
  for (int seed : {0, 1, 2}) {
    const std::string out = f.dir.file("seed" + std::to_string(seed));
    const Run r = Motionfork(f.Train(
        f.Config("s" + std::to_string(seed) + ".yaml", TinyConfig(true, 4, 40, seed)), out));
    REQUIRE(r.status == 0);
    seeds.push_back(LossCurve(out + "/log.csv"));
  }
  const Run r =
      Motionfork(f.Train(f.Config("two.yaml", TinyConfig(true, 4, 40, 0)), f.dir.file("two")) +
                 " --nproc-per-node 2");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const std::vector<double> two = LossCurve(f.dir.file("two") + "/log.csv");
  REQUIRE(two.size() == 4);
  for (size_t e = 0; e < two.size(); ++e) {
    double lo = seeds[0][e], hi = lo;
    for (const auto& s : seeds) lo = std::min(lo, s[e]), hi = std::max(hi, s[e]);
    const double spread = hi - lo;
    INFO("epoch " << e + 1 << ": two workers " << two[e] << ", one worker " << lo << ".." << hi);
    CHECK(two[e] >= lo - spread);
    CHECK(two[e] <= hi + spread);
  }
}

TEST_CASE("four workers on two nodes train, a killed worker stops the run, two workers resume") {
  Fixture f;
  const std::string config = f.Config("long.yaml", TinyConfig(true, 30, 400));
  const std::string out = f.dir.file("run"), log = out + "/log.csv";
  const int port = motionfork::FreeLocalPort();
  const std::string node = " --nproc-per-node 2 --nnodes 2 --master-addr 127.0.0.1 --master-port " +
                           std::to_string(port) + " --node-rank ";
  // Both "nodes" in the background, each with its output and exit status in files (the subshell's
  // own output away from RunShell's pipe, which would otherwise wait for it).
  for (int n : {0, 1}) {
    const std::string base = f.dir.file("node" + std::to_string(n));
    RunShell("(timeout 300 " MOTIONFORK_BINARY " --cache-dir none " + f.Train(config, out) + node +
             std::to_string(n) + " > " + base + ".out 2>&1; echo $? > " + base +
             ".rc) > /dev/null 2>&1 &");
  }
  auto finished = [&](int n) { return fs::exists(f.dir.file("node" + std::to_string(n) + ".rc")); };
  const auto start = std::chrono::steady_clock::now();
  while (Rows(log) < 2 && std::chrono::steady_clock::now() - start < std::chrono::seconds(200) &&
         !finished(0))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  INFO(ReadFileBytes(f.dir.file("node0.out")));
  REQUIRE(Rows(log) >= 2);
  const pid_t victim = WorkerPid(3, out);
  REQUIRE(victim > 0);
  REQUIRE(kill(victim, SIGKILL) == 0);
  const auto killed = std::chrono::steady_clock::now();
  while (!(finished(0) && finished(1)) &&
         std::chrono::steady_clock::now() - killed < std::chrono::seconds(90))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  REQUIRE(finished(0));
  REQUIRE(finished(1));
  CHECK(std::chrono::steady_clock::now() - killed < std::chrono::seconds(60));
  const std::string out0 = ReadFileBytes(f.dir.file("node0.out"));
  const std::string out1 = ReadFileBytes(f.dir.file("node1.out"));
  INFO(out0 << "\n--- node 1 ---\n" << out1);
  CHECK(std::stoi(ReadFileBytes(f.dir.file("node0.rc"))) != 0);
  CHECK(std::stoi(ReadFileBytes(f.dir.file("node1.rc"))) == 128 + SIGKILL);
  CHECK_THAT(out1,
             Contains("worker rank 3 (pid " + std::to_string(victim) + ") was killed by signal 9"));
  CHECK_THAT(out0, Contains("rank 3 stopped"));
  const int done = Rows(log);
  REQUIRE(done >= 2);
  REQUIRE(done < 30);

  // The same command with two workers on one node resumes from the last checkpoint and finishes.
  const Run r = Motionfork(f.Train(config, out) + " --nproc-per-node 2");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output,
             Contains("resuming from " + out + "/checkpoint at epoch " + std::to_string(done + 1)));
  CHECK(Rows(log) == 30);
}

TEST_CASE("a worker with a wrong WORLD_SIZE or no master stops with a clear error") {
  Fixture f;
  const std::string config = f.Config("tiny.yaml", TinyConfig(false, 1, 8));
  const std::string env = "MOTIONFORK_JOIN_TIMEOUT=3 MASTER_ADDR=127.0.0.1 MASTER_PORT=" +
                          std::to_string(motionfork::FreeLocalPort());
  Run r = RunShell(env + " WORLD_SIZE=3 RANK=0 " MOTIONFORK_BINARY " --cache-dir none " +
                   f.Train(config, f.dir.file("a")) + " 2>&1");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("rank 0: ") && Contains("only 1 of WORLD_SIZE=3 workers reached"));
  r = RunShell(env + " WORLD_SIZE=2 RANK=1 " MOTIONFORK_BINARY " --cache-dir none " +
               f.Train(config, f.dir.file("b")) + " 2>&1");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("cannot reach the master (rank 0) at 127.0.0.1:"));
  r = RunShell("WORLD_SIZE=2 RANK=5 " MOTIONFORK_BINARY " --cache-dir none " +
               f.Train(config, f.dir.file("c")) + " 2>&1");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("environment variable RANK: expected 0..1"));
}
