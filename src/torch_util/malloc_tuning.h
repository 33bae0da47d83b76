// glibc hands freed blocks above its mmap threshold back to the system, and trims the heap top;
// LibTorch allocates and frees tensors of hundreds of kB to MBs all the time, so each new tensor
// page-faults its memory in again (clearing pages took a quarter of the generator's inference time
// here). Programs (not libraries) call KeepFreedMemory() once at start-up.
#pragma once

namespace motionfork {

// Blocks up to 32 MB come from the heap, and up to 256 MB of freed heap stays in the process.
void KeepFreedMemory();

}  // namespace motionfork
