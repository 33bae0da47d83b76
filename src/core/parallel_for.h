// Work split across threads so that the result does not depend on how many: items are taken in
// turn, each writes only its own result, and the caller combines them in item order afterwards.
// Random draws use ItemSeed(seed, item), never one generator shared across items.
#pragma once

#include <cstdint>
#include <functional>

namespace motionfork {

// Runs fn(item, worker) for every item in [0, count) on min(threads, count) threads (the calling
// thread is worker 0; threads < 1 counts as 1). `worker` in [0, threads) indexes per-thread
// scratch. When items throw, the other threads stop after their current item and the exception
// of the lowest failing item is rethrown: the one a single thread would have met first.
// Thread-local state (LibTorch's grad mode, for one) is not carried into the other threads.
void ParallelFor(int count, int threads, const std::function<void(int item, int worker)>& fn);

// The seed of item `item` of a run seeded `seed`: a SplitMix64 mix of both.
uint64_t ItemSeed(uint64_t seed, int item);

}  // namespace motionfork
