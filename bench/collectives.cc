// Benchmark: the sums synchronised batch norm makes, by the two routes DataParallel has, A/B
// interleaved in one run: through c10d's ProcessGroupGloo (its worker thread and Gloo's event
// loop) and on Gloo's synchronous pairs (the calling thread; SumValues' default up to
// kSmallSumBytes).
//
//   bench_collectives [ROUNDS] [WORK_MS] [VALUES]
//   defaults: 3 rounds, 2 ms of work between sums, 8,192 doubles (64 KB: one normalised layer
//   of the Bandai generator, its 16 x 256 means and squares)
//
// Two worker processes on 127.0.0.1, one thread each, as `--nproc-per-node 2` runs them; between
// sums each does the same fixed matrix work (so neither waits for a slower other), as the layers
// between two batch-norm sums do. Prints the mean time of a sum per route and round. Run on an
// idle machine: both cores are used.
#include <sys/wait.h>
#include <torch/torch.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "launch/worker_launcher.h"
#include "launch/worker_place.h"
#include "torch_util/data_parallel.h"
#include "torch_util/threads.h"

namespace {

using Clock = std::chrono::steady_clock;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// Rank `rank` of two: per round and route, `sums` sums of `values` doubles, each after the
// matrix products that take about work_ms here (counted once, then the same count every time).
int Worker(int rank, int port, int rounds, double work_ms, size_t values) {
  motionfork::PinThreads(1);
  motionfork::WorkerPlace place;
  place.rank = place.local_rank = rank;
  place.world_size = place.local_world_size = 2;
  place.master_addr = "127.0.0.1";
  place.master_port = port;
  motionfork::DataParallel workers(place, std::chrono::seconds(60), std::chrono::seconds(60));
  const torch::Tensor a = torch::randn({128, 128}), b = torch::randn({128, 128});
  // Products per work_ms, measured by rank 0 and shared, so both do the same work.
  std::vector<double> per_ms = {0};
  if (rank == 0) {
    const auto start = Clock::now();
    int n = 0;
    while (Ms(Clock::now() - start) < 200) {
      torch::mm(a, b);
      ++n;
    }
    per_ms[0] = n / Ms(Clock::now() - start);
  }
  workers.SumValues(&per_ms);
  const int products = std::max(1, static_cast<int>(per_ms[0] * work_ms));
  const int sums = 300;
  std::vector<double> v(values, 1.0);
  for (int round = 1; round <= rounds; ++round) {
    for (const bool small : {false, true}) {
      workers.set_small_sum_bytes(small ? motionfork::DataParallel::kSmallSumBytes : 0);
      workers.Barrier();
      double summing = 0;
      const auto start = Clock::now();
      for (int i = 0; i < sums; ++i) {
        for (int p = 0; p < products; ++p) torch::mm(a, b);
        const auto t = Clock::now();
        workers.SumValues(&v, "benchmark sum");
        summing += Ms(Clock::now() - t);
        std::fill(v.begin(), v.end(), 1.0);
      }
      const double total = Ms(Clock::now() - start);
      if (rank == 0) {
        std::printf(
            "round %d: %-44s %.3f ms a sum (%.1f%% of the loop)\n", round,
            small ? "synchronous pairs, calling thread:" : "ProcessGroupGloo (worker thread):",
            summing / sums, 100 * summing / total);
        std::fflush(stdout);
      }
    }
  }
  workers.Barrier();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 3;
  const double work_ms = argc > 2 ? std::atof(argv[2]) : 2.0;
  const size_t values = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 8192;
  const int port = motionfork::FreeLocalPort();
  std::printf(
      "two workers on 127.0.0.1, %zu doubles (%.0f KB) a sum, %.1f ms of work between sums, "
      "300 sums a route and round\n",
      values, values * 8 / 1024.0, work_ms);
  std::fflush(stdout);
  std::vector<pid_t> children;
  for (int rank = 0; rank < 2; ++rank) {
    const pid_t pid = fork();
    if (pid == 0) std::_Exit(Worker(rank, port, rounds, work_ms, values));
    children.push_back(pid);
  }
  int failed = 0;
  for (const pid_t pid : children) {
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) ++failed;
  }
  if (failed) std::fprintf(stderr, "bench_collectives: %d worker(s) failed\n", failed);
  return failed ? 1 : 0;
}
