// glibc hands freed blocks above its mmap threshold back to the system, and trims the heap top;
// LibTorch allocates and frees tensors of hundreds of kB to MBs all the time, so each new tensor
// page-faults its memory in again (clearing pages took a quarter of the generator's inference time
// here). Programs (not libraries) call KeepFreedMemory() once at start-up.
#pragma once

namespace motionfork {

// Every block comes from the heap, and up to 1 GB of freed heap stays in the process (the
// process's peak memory is unchanged; its memory is not returned to the system until it exits).
void KeepFreedMemory();

}  // namespace motionfork
