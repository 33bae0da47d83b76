// The local launcher behind `--nproc-per-node N`: starts N worker processes of this machine's
// share of a run with torchrun's environment (RANK, WORLD_SIZE, LOCAL_RANK, LOCAL_WORLD_SIZE,
// MASTER_ADDR, MASTER_PORT), as torchrun does, and watches them: when one fails or is killed it
// says which (rank, pid, exit status or signal), gives the others a grace period to stop on their
// own (their collectives fail and name the rank), then terminates them. Threads per worker are set
// so that workers x threads never exceeds the cores (OMP_NUM_THREADS, OPENBLAS_NUM_THREADS,
// MOTIONFORK_THREADS, unless already set).
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace motionfork {

struct LaunchOptions {
  int nproc_per_node = 1;
  int nnodes = 1;
  int node_rank = 0;
  std::string master_addr;  // "" = 127.0.0.1 (one node only)
  int master_port = 0;      // 0 = a free port (one node) / 29500, torchrun's default (several)
  std::chrono::seconds grace{15};
};

// True when the options ask for more than this one process (nproc_per_node > 1 or nnodes > 1).
bool LaunchRequested(const LaunchOptions& options);

// Refuses (std::invalid_argument, naming the flag) counts < 1, node_rank outside 0..nnodes-1, a
// port outside 1..65535, and several nodes without --master-addr.
void CheckLaunchOptions(const LaunchOptions& options);

// argv without the launcher's own flags (--nproc-per-node, --nnodes, --node-rank, --master-addr,
// --master-port, as "--flag value" or "--flag=value"): the command line each worker runs.
std::vector<std::string> WithoutLauncherFlags(const std::vector<std::string>& argv);

// Runs `argv` (argv[0] is the program's name; the program run is this executable) as
// options.nproc_per_node workers and waits for them. Returns 0 when all succeed, else the exit
// status of the first worker that failed (128 + signal when it was killed). `note` receives the
// launcher's messages (what it started, which worker failed).
int LaunchWorkers(const LaunchOptions& options, const std::vector<std::string>& argv,
                  const std::function<void(const std::string&)>& note);

// A TCP port on 127.0.0.1 that was free a moment ago.
int FreeLocalPort();

}  // namespace motionfork
