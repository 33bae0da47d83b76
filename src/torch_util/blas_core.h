// OpenBLAS picks its kernels from the CPU model when the library loads. On a CPU newer than the
// OpenBLAS build knows (Debian's 0.3.21 on a family 6 model 207 Xeon, say), it falls back to
// "Prescott", an SSE3 kernel about 5x slower than the AVX-512 one (20 vs 118 GFLOP/s of float32
// matrix products measured here). The choice can only be changed through $OPENBLAS_CORETYPE
// before the library loads, so a program that wants the fast kernels re-executes itself with it
// set. No LibTorch in this header.
#pragma once

#include <string>

namespace motionfork {

// The kernel family OpenBLAS runs ("SkylakeX", "Prescott", ...), or "" when the process does not
// use OpenBLAS.
std::string BlasCoreName();

// The OPENBLAS_CORETYPE this CPU supports best when OpenBLAS fell back to a generic kernel
// ("SkylakeX" with AVX-512, "Haswell" with AVX2 + FMA, "SandyBridge" with AVX), else "" (OpenBLAS
// chose well, the user set $OPENBLAS_CORETYPE, or this is not OpenBLAS).
std::string BetterBlasCore();

// Call first thing in main(): when BetterBlasCore() names a kernel, sets $OPENBLAS_CORETYPE and
// re-executes the program (/proc/self/exe, same arguments); otherwise, or when exec fails,
// returns and the program runs with what it has. $MOTIONFORK_BLAS_REEXEC=0 turns this off.
void UseFastBlasKernels(char** argv);

}  // namespace motionfork
