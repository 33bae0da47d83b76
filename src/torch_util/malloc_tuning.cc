#include "torch_util/malloc_tuning.h"

#include <malloc.h>

namespace motionfork {

void KeepFreedMemory() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest allowed on 64-bit systems
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

}  // namespace motionfork
