// Where this process stands in a run of several worker processes, read the way PyTorch's launchers
// describe it (torchrun, Slurm through a torchrun-style wrapper, Kubernetes jobs): RANK,
// WORLD_SIZE, LOCAL_RANK, LOCAL_WORLD_SIZE, MASTER_ADDR, MASTER_PORT. Plain C++: the command reads
// it before LibTorch starts (only rank 0 prints).
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace motionfork {

struct WorkerPlace {
  int rank = 0;              // RANK
  int world_size = 1;        // WORLD_SIZE
  int local_rank = 0;        // LOCAL_RANK (default: RANK)
  int local_world_size = 1;  // LOCAL_WORLD_SIZE (default: WORLD_SIZE)
  std::string master_addr;   // MASTER_ADDR
  int master_port = 0;       // MASTER_PORT
};

// The place from the environment. WORLD_SIZE absent: one worker (rank 0 of 1). Malformed or
// inconsistent values (RANK outside 0..WORLD_SIZE-1, no MASTER_ADDR/MASTER_PORT for several
// workers) are a std::invalid_argument naming the variable, what was expected and what was found.
WorkerPlace WorkerPlaceFromEnvironment();

// True unless this process is a worker of rank > 0: rank 0 alone writes a run's files.
bool IsRankZero();

// In a run of several workers (WorkerPlaceFromEnvironment), rank 0 alone prints: a worker of
// another rank sends its standard output to /dev/null (errors stay on standard error) and sets
// *quiet (no progress bars). Returns "rank N: " to put before this worker's error messages, ""
// for one worker.
std::string FollowRankZeroOutput(bool* quiet);

// How long a collective may wait for the other workers: $MOTIONFORK_DIST_TIMEOUT seconds, default
// 60 (a worker that died is noticed at once; this bounds a network that went silent).
std::chrono::milliseconds DistributedTimeout();
// How long the rendezvous waits for every worker to arrive (each arrives once it has loaded its
// data): $MOTIONFORK_JOIN_TIMEOUT seconds, default 600 (torchrun's join timeout).
std::chrono::milliseconds JoinTimeout();

// A contiguous share [begin, end) of n items; the shares of ranks 0..world-1 tile [0, n) in order
// and differ in size by at most one.
struct Share {
  int64_t begin = 0, end = 0;
  int64_t size() const { return end - begin; }
};
Share ShareOf(int64_t n, int rank, int world_size);

// Cores this process may run on (its CPU affinity).
int CoresAvailable();

}  // namespace motionfork
