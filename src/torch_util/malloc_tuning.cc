#include "torch_util/malloc_tuning.h"

#include <malloc.h>

namespace motionfork {

void KeepFreedMemory() {
  // Every block from the heap (no mmap: glibc caps its mmap threshold at 32 MB, and a training
  // step's 40 MB tensors were then page-faulted and cleared anew each step, 28% of its time), and
  // freed heap never trimmed (a training step frees gigabytes at once after its backward pass).
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, -1);
}

}  // namespace motionfork
