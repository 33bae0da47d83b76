// Thread pinning for LibTorch and the BLAS under it. Two cores are shared between a training run
// and everything else: pin both pools before timing or training, or they oversubscribe.
#pragma once

namespace motionfork {

// Sets LibTorch's intra-op and inter-op pools and OpenBLAS's pool to `threads` (>= 1).
// Inter-op threads can only be set once per process; later calls leave it as it is.
void PinThreads(int threads);

// Threads for a job that shares its windows across threads (--threads: `requested`, or every core
// when 0), with LibTorch and OpenBLAS pinned to one thread each so that the results do not depend
// on the count (core/parallel_for.h).
int WindowThreads(int requested);

// Threads to use by default: $MOTIONFORK_THREADS if set, else 1.
int DefaultThreads();

// Gives every thread of this process but the calling one a short scheduler slice (0.1 ms; Linux's
// EEVDF scheduler, 6.12 and later; elsewhere nothing changes). For the workers of a data-parallel
// run: their communication threads then preempt a computing thread as soon as a message arrives
// instead of waiting out its slice (about 3 ms), which on a machine with every core computing is
// most of a collective's time. Returns how many threads took it.
int ShortenHelperThreadSlices();

}  // namespace motionfork
