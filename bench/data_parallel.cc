// Benchmark: data-parallel training and multi-threaded evaluation, as users run them (the
// motionfork command), one worker against two in turns (A/B interleaved), on the Bandai set.
//
//   bench_data_parallel [DATA_DIR] [ROUNDS] [MOTIONFORK] [CONFIG] [EVAL]
//   defaults: ../shared/data/bandai 3 <build>/apps/motionfork/motionfork bandai 1 (0: training
//   only)
//
// Per round: one generator epoch of CONFIG (configs/models/CONFIG.yaml: the same windows an epoch)
// with 1 worker, then with `--nproc-per-node 2`; `eval` of the shipped model on the test split
// with --threads 1, then 2. Prints each time, the speed-ups, the gradient all-reduce's and the
// synchronised batch norm's shares of a 2-worker step, and from it a projection of the speed-up at
// 8, 32 and 128 workers over a network of stated bandwidth and latency (ring all-reduce; a step
// keeps at least one history per worker). Run on an idle machine: both cores are used.
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Output {
  int status = 0;
  std::string text;
  double seconds = 0;
};

Output RunCommand(const std::string& command) {
  const auto start = std::chrono::steady_clock::now();
  Output o;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof(buf), pipe)) > 0) o.text.append(buf, n);
  const int st = pclose(pipe);
  o.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (o.status != 0) {
    std::fprintf(stderr, "failed (%d): %s\n%s\n", o.status, command.c_str(), o.text.c_str());
    std::exit(1);
  }
  return o;
}

// The epoch's seconds from a training log (OUT/log.csv, third column).
double EpochSeconds(const fs::path& log) {
  std::ifstream in(log);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  std::stringstream s(row);
  std::string cell;
  std::getline(s, cell, ',');
  std::getline(s, cell, ',');
  std::getline(s, cell, ',');
  return std::stod(cell);
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "../shared/data/bandai";
  const int rounds = argc > 2 ? std::stoi(argv[2]) : 3;
  const fs::path self = fs::canonical("/proc/self/exe");
  const std::string binary =
      argc > 3 ? argv[3]
               : (self.parent_path().parent_path() / "apps/motionfork/motionfork").string();
  const std::string config = argc > 4 ? argv[4] : "bandai";
  const bool with_eval = argc > 5 ? std::stoi(argv[5]) != 0 : true;
  const fs::path scratch = fs::temp_directory_path() / "motionfork_bench_data_parallel";
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  const std::string cache = (scratch / "cache").string();
  const std::string models = (self.parent_path().parent_path().parent_path() / "models").string();
  const std::string common = binary + " -q --cache-dir " + cache + " ";

  // Warm-up: the dataset and the pseudo multimodal futures into the cache, the multimodal sets.
  RunCommand(common + "train --config " + config + " --data " + data + " --out " +
             (scratch / "warm").string() + " --epochs 1 --stop-after 1");
  if (with_eval)
    RunCommand(common + "eval --protocol bandai --data " + data + " --baseline zero -k 2");

  std::vector<double> train1, train2, eval1, eval2, reduce_share, step_ms, reduce_ms, sync_share;
  double grad_mb = 0;
  int steps = 0;
  const std::regex reduce_line(
      R"(gradient all-reduce: ([0-9.]+) s of ([0-9.]+) s \([0-9.]+%\), ([0-9]+) steps, ([0-9.]+) MB)");
  const std::regex sync_line(R"(batch-norm sums: ([0-9.]+) s of ([0-9.]+) s)");
  for (int r = 0; r < rounds; ++r) {
    for (int workers : {1, 2}) {
      const fs::path out = scratch / ("w" + std::to_string(workers) + "_" + std::to_string(r));
      const Output o =
          RunCommand(common + "train --config " + config + " --data " + data + " --out " +
                     out.string() + " --epochs 1" + (workers > 1 ? " --nproc-per-node 2" : ""));
      const double s = EpochSeconds(out / "log.csv");
      (workers == 1 ? train1 : train2).push_back(s);
      std::printf("round %d: generator epoch, %d worker(s): %.2f s\n", r + 1, workers, s);
      std::smatch m;
      if (workers > 1 && std::regex_search(o.text, m, sync_line))
        sync_share.push_back(std::stod(m[1]) / std::stod(m[2]));
      if (workers > 1 && std::regex_search(o.text, m, reduce_line)) {
        reduce_share.push_back(std::stod(m[1]) / std::stod(m[2]));
        steps = std::stoi(m[3]);
        grad_mb = std::stod(m[4]);
        reduce_ms.push_back(1000 * std::stod(m[1]) / steps);
        step_ms.push_back(1000 * std::stod(m[2]) / steps);
      }
      std::fflush(stdout);
    }
    for (int threads : {1, 2}) {
      if (!with_eval) break;
      const Output o = RunCommand(common + "eval --protocol bandai --data " + data + " --model " +
                                  models + "/bandai --threads " + std::to_string(threads));
      (threads == 1 ? eval1 : eval2).push_back(o.seconds);
      std::printf("round %d: eval of the test split, %d thread(s): %.2f s\n", r + 1, threads,
                  o.seconds);
      std::fflush(stdout);
    }
  }
  const double t1 = Median(train1), t2 = Median(train2);
  std::printf("\ngenerator epoch: 1 worker %.2f s, 2 workers %.2f s (medians): %.2fx\n", t1, t2,
              t1 / t2);
  if (with_eval) {
    std::printf("eval, test split: 1 thread %.2f s, 2 threads %.2f s (medians): %.2fx\n",
                Median(eval1), Median(eval2), Median(eval1) / Median(eval2));
  }
  if (!sync_share.empty()) {
    std::printf("2 workers: synchronised batch norm's sums %.1f%% of the run (median)\n",
                100 * Median(sync_share));
  }
  if (reduce_share.empty()) return 0;
  const double share = Median(reduce_share);
  std::printf(
      "2 workers: gradient all-reduce %.2f ms of a %.2f ms step (%.1f%%), %.2f MB of gradients, "
      "%d steps\n",
      Median(reduce_ms), Median(step_ms), 100 * share, grad_mb, steps);

  // Projection. A 2-worker step less its all-reduce is the compute of 8 histories; it is scaled to
  // each worker's share (at least one history), which counts the costs that do not shrink with the
  // share (Adam's update of every weight) as if they did and so flatters many workers; a ring
  // all-reduce of S bytes over W workers costs 2 (W - 1) / W * S / bandwidth + 2 (W - 1) latency.
  const double bandwidth = 10e9 / 8, latency = 50e-6;  // 10 Gbit/s Ethernet, 50 us a message
  const int batch = 16, windows = steps * batch;
  const double compute1 = (Median(step_ms) - Median(reduce_ms)) / 1000 * 2;  // 16 histories
  std::printf(
      "projection (10 Gbit/s, 50 us latency; %d windows an epoch, at least one history per "
      "worker):\n",
      windows);
  for (int w : {2, 8, 32, 128}) {
    const double per_worker = std::max(1.0, static_cast<double>(batch) / w);
    const double step = compute1 * per_worker / batch +
                        2.0 * (w - 1) / w * grad_mb * 1e6 / bandwidth + 2.0 * (w - 1) * latency;
    const double epoch = windows / (per_worker * w) * step;
    std::printf("  %3d workers: %.2f s an epoch, %.1fx one worker\n", w, epoch, t1 / epoch);
  }
  fs::remove_all(scratch);
  return 0;
}
