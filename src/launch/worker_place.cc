#include "launch/worker_place.h"

#include <sched.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <thread>

namespace motionfork {

namespace {

// An environment variable as a whole number >= 0; `fallback` when unset or empty.
int EnvInt(const char* name, int fallback) {
  const char* text = std::getenv(name);
  if (!text || !*text) return fallback;
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (errno != 0 || *end != '\0' || v < 0 || v > INT_MAX) {
    throw std::invalid_argument(std::string("environment variable ") + name +
                                ": expected a whole number >= 0, found '" + text + "'");
  }
  return static_cast<int>(v);
}

std::string EnvText(const char* name) {
  const char* text = std::getenv(name);
  return text ? text : "";
}

}  // namespace

WorkerPlace WorkerPlaceFromEnvironment() {
  WorkerPlace p;
  if (EnvText("WORLD_SIZE").empty()) return p;
  p.world_size = EnvInt("WORLD_SIZE", 1);
  if (p.world_size < 1)
    throw std::invalid_argument("environment variable WORLD_SIZE: expected >= 1, found 0");
  const std::string range = "0.." + std::to_string(p.world_size - 1) +
                            " (WORLD_SIZE=" + std::to_string(p.world_size) + ")";
  p.rank = EnvInt("RANK", -1);
  if (p.rank < 0) {
    throw std::invalid_argument("environment variable RANK: expected this worker's rank " + range +
                                ", found none");
  }
  if (p.rank >= p.world_size) {
    throw std::invalid_argument("environment variable RANK: expected " + range + ", found " +
                                std::to_string(p.rank));
  }
  p.local_rank = EnvInt("LOCAL_RANK", p.rank);
  p.local_world_size = std::max(1, EnvInt("LOCAL_WORLD_SIZE", p.world_size));
  if (p.world_size == 1) return p;
  p.master_addr = EnvText("MASTER_ADDR");
  p.master_port = EnvInt("MASTER_PORT", 0);
  if (p.master_addr.empty() || p.master_port == 0 || p.master_port > 65535) {
    throw std::invalid_argument(
        "environment variables MASTER_ADDR and MASTER_PORT: expected the host and port (1..65535) "
        "of rank 0 for WORLD_SIZE=" +
        std::to_string(p.world_size) + ", found MASTER_ADDR='" + p.master_addr + "' MASTER_PORT='" +
        EnvText("MASTER_PORT") + "'");
  }
  return p;
}

std::string FollowRankZeroOutput(bool* quiet) {
  const WorkerPlace place = WorkerPlaceFromEnvironment();
  if (place.world_size <= 1) return "";
  if (place.rank != 0 && std::freopen("/dev/null", "w", stdout)) *quiet = true;
  return "rank " + std::to_string(place.rank) + ": ";
}

bool IsRankZero() { return WorkerPlaceFromEnvironment().rank == 0; }

std::chrono::milliseconds DistributedTimeout() {
  const int seconds = EnvInt("MOTIONFORK_DIST_TIMEOUT", 60);
  return std::chrono::milliseconds(1000LL * std::max(1, seconds));
}

std::chrono::milliseconds JoinTimeout() {
  const int seconds = EnvInt("MOTIONFORK_JOIN_TIMEOUT", 600);
  return std::chrono::milliseconds(1000LL * std::max(1, seconds));
}

Share ShareOf(int64_t n, int rank, int world_size) {
  const int64_t w = std::max(1, world_size), r = rank;
  return {n * r / w, n * (r + 1) / w};
}

int CoresAvailable() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace motionfork
