// torchrun's environment read as a worker's place; shares of a batch; the launcher's flags.
#include "launch/worker_place.h"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <initializer_list>
#include <string>
#include <vector>

#include "launch/worker_launcher.h"

using Catch::Contains;
using motionfork::LaunchOptions;
using motionfork::ShareOf;
using motionfork::WorkerPlaceFromEnvironment;

namespace {

// Sets the run's variables for one scope, then clears them.
struct Environment {
  explicit Environment(std::initializer_list<std::pair<const char*, const char*>> vars) {
    for (const auto& [k, v] : vars) setenv(k, v, 1);
  }
  ~Environment() {
    for (const char* k :
         {"RANK", "WORLD_SIZE", "LOCAL_RANK", "LOCAL_WORLD_SIZE", "MASTER_ADDR", "MASTER_PORT"})
      unsetenv(k);
  }
};

}  // namespace

TEST_CASE("no WORLD_SIZE: one worker of rank 0") {
  Environment env({});
  const auto p = WorkerPlaceFromEnvironment();
  CHECK(p.rank == 0);
  CHECK(p.world_size == 1);
  CHECK(motionfork::IsRankZero());
}

TEST_CASE("torchrun's variables are read as they are") {
  Environment env({{"RANK", "3"},
                   {"WORLD_SIZE", "4"},
                   {"LOCAL_RANK", "1"},
                   {"LOCAL_WORLD_SIZE", "2"},
                   {"MASTER_ADDR", "node0.cluster"},
                   {"MASTER_PORT", "29500"}});
  const auto p = WorkerPlaceFromEnvironment();
  CHECK(p.rank == 3);
  CHECK(p.world_size == 4);
  CHECK(p.local_rank == 1);
  CHECK(p.local_world_size == 2);
  CHECK(p.master_addr == "node0.cluster");
  CHECK(p.master_port == 29500);
  CHECK_FALSE(motionfork::IsRankZero());
}

TEST_CASE("bad run variables name the variable, what was expected and what was found") {
  {
    Environment env(
        {{"WORLD_SIZE", "2"}, {"RANK", "2"}, {"MASTER_ADDR", "h"}, {"MASTER_PORT", "1"}});
    REQUIRE_THROWS_WITH(WorkerPlaceFromEnvironment(),
                        Contains("RANK") && Contains("expected 0..1") && Contains("found 2"));
  }
  {
    Environment env({{"WORLD_SIZE", "two"}});
    REQUIRE_THROWS_WITH(WorkerPlaceFromEnvironment(),
                        Contains("WORLD_SIZE") && Contains("found 'two'"));
  }
  {
    Environment env({{"WORLD_SIZE", "2"}, {"RANK", "0"}});
    REQUIRE_THROWS_WITH(WorkerPlaceFromEnvironment(), Contains("MASTER_ADDR and MASTER_PORT") &&
                                                          Contains("found MASTER_ADDR=''"));
  }
  {
    Environment env({{"WORLD_SIZE", "2"}});
    REQUIRE_THROWS_WITH(WorkerPlaceFromEnvironment(), Contains("RANK") && Contains("found none"));
  }
}

TEST_CASE("shares tile a batch in order and differ by at most one") {
  for (int world : {1, 2, 3, 4, 7}) {
    for (int n : {7, 8, 16, 101}) {
      int64_t next = 0, smallest = n, largest = 0;
      for (int r = 0; r < world; ++r) {
        const auto s = ShareOf(n, r, world);
        CHECK(s.begin == next);
        next = s.end;
        smallest = std::min(smallest, s.size());
        largest = std::max(largest, s.size());
      }
      CHECK(next == n);
      CHECK(largest - smallest <= 1);
    }
  }
}

TEST_CASE("the workers' command line drops the launcher's flags in both spellings") {
  const std::vector<std::string> argv = {"motionfork",
                                         "train",
                                         "--nproc-per-node",
                                         "2",
                                         "--config",
                                         "x.yaml",
                                         "--nnodes=2",
                                         "--node-rank",
                                         "1",
                                         "--out",
                                         "run",
                                         "--master-addr",
                                         "host",
                                         "--master-port=9"};
  CHECK(motionfork::WithoutLauncherFlags(argv) ==
        std::vector<std::string>{"motionfork", "train", "--config", "x.yaml", "--out", "run"});
}

TEST_CASE("launcher options are checked") {
  LaunchOptions o;
  CHECK_FALSE(motionfork::LaunchRequested(o));
  o.nproc_per_node = 2;
  CHECK(motionfork::LaunchRequested(o));
  CHECK_NOTHROW(motionfork::CheckLaunchOptions(o));
  o.nnodes = 2;
  REQUIRE_THROWS_WITH(motionfork::CheckLaunchOptions(o), Contains("--master-addr"));
  o.master_addr = "node0";
  o.node_rank = 2;
  REQUIRE_THROWS_WITH(motionfork::CheckLaunchOptions(o),
                      Contains("--node-rank: expected 0..1") && Contains("found 2"));
}
