#include "core/parallel_for.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace motionfork;

TEST_CASE("ParallelFor runs every item once, on at most the threads asked for") {
  for (int threads : {0, 1, 2, 4, 50}) {
    for (int count : {0, 1, 3, 37}) {
      std::vector<std::atomic<int>> runs(static_cast<size_t>(count));
      std::atomic<int> worst_worker{0};
      ParallelFor(count, threads, [&](int item, int worker) {
        ++runs[static_cast<size_t>(item)];
        int seen = worst_worker.load();
        while (worker > seen && !worst_worker.compare_exchange_weak(seen, worker)) {
        }
      });
      for (int i = 0; i < count; ++i) CHECK(runs[static_cast<size_t>(i)] == 1);
      CHECK(worst_worker < std::max(1, std::min(threads, std::max(count, 1))));
    }
  }
}

TEST_CASE("ParallelFor uses more than one thread when asked") {
  std::mutex lock;
  std::set<std::thread::id> ids;
  std::atomic<int> inside{0};
  ParallelFor(2, 2, [&](int, int) {
    {
      std::lock_guard<std::mutex> guard(lock);
      ids.insert(std::this_thread::get_id());
    }
    ++inside;
    // Both items are in flight at once: each waits (bounded) for the other to start.
    for (int spin = 0; spin < 2000 && inside < 2; ++spin)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  CHECK(ids.size() == 2);
}

TEST_CASE("ParallelFor rethrows the lowest failing item's error, whatever the threads") {
  for (int threads : {1, 2, 3}) {
    try {
      ParallelFor(40, threads, [](int item, int) {
        if (item == 7 || item == 30)
          throw std::runtime_error("item " + std::to_string(item) + " failed");
        std::this_thread::sleep_for(std::chrono::microseconds(100 * (item % 3)));
      });
      FAIL("expected an exception");
    } catch (const std::runtime_error& e) {
      CHECK(std::string(e.what()) == "item 7 failed");
    }
  }
}

TEST_CASE("ItemSeed depends on both the seed and the item, and only on them") {
  CHECK(ItemSeed(0, 0) == ItemSeed(0, 0));
  std::set<uint64_t> seeds;
  for (uint64_t s : {0ull, 1ull, 12345ull})
    for (int i = 0; i < 100; ++i) seeds.insert(ItemSeed(s, i));
  CHECK(seeds.size() == 300);
  // SplitMix64's first output for state 0 (Vigna's reference generator), as WindowSeed has used.
  CHECK(ItemSeed(0, 0) == 0xE220A8397B1DCDAFull);
}
