#include "core/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace motionfork {

void ParallelFor(int count, int threads, const std::function<void(int item, int worker)>& fn) {
  if (count <= 0) return;
  const int workers = std::max(1, std::min(threads, count));
  std::atomic<int> next{0};
  std::vector<std::exception_ptr> failures(static_cast<size_t>(count));
  auto work = [&](int worker) {
    // Items are handed out in increasing order, so every item below a taken one was taken too.
    for (int i = next++; i < count; i = next++) {
      try {
        fn(i, worker);
      } catch (...) {
        failures[static_cast<size_t>(i)] = std::current_exception();
        next = count;  // the others stop after their current item
      }
    }
  };
  if (workers == 1) {
    work(0);
  } else {
    std::vector<std::thread> pool;
    for (int w = 1; w < workers; ++w) pool.emplace_back(work, w);
    work(0);
    for (std::thread& t : pool) t.join();
  }
  for (const std::exception_ptr& f : failures) {
    if (f) std::rethrow_exception(f);
  }
}

uint64_t ItemSeed(uint64_t seed, int item) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (static_cast<uint64_t>(item) + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace motionfork
