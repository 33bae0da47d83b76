// glibc hands freed blocks above its mmap threshold back to the system, and trims the heap top;
// LibTorch allocates and frees tensors of hundreds of kB to MBs all the time, so each new tensor
// page-faults its memory in again (clearing pages took a quarter of the generator's inference time
// here). Programs (not libraries) call KeepFreedMemory() once at start-up.
#pragma once

namespace motionfork {

// Every block comes from the heap, and freed heap stays in the process (its peak memory is
// unchanged; memory is not returned to the system until the process exits).
void KeepFreedMemory();

}  // namespace motionfork
