// Which implementation the kernels run. Every kernel has a portable backend (scalar C++ the
// compiler vectorises at the default flags, built everywhere) and most an AVX-512 one
// (*_avx512.cc, built when CMake's MOTIONFORK_AVX512 is ON and the compiler takes
// -march=skylake-avx512). The AVX-512 backend runs when it was built and the CPU has AVX-512
// (Cpu().avx512), unless UsePortableKernels(true); the choice is made per call, so a switch takes
// effect at once. (MOTIONFORK_FAST_GENERATOR=0 is a different switch: Forecaster then runs the
// LibTorch network instead of FusedGenerator.)
#pragma once

namespace motionfork::kernels {

enum class Backend { kPortable, kAvx512 };

// True when this build compiled the AVX-512 backend.
bool Avx512Built();

// The backend the kernels run now.
Backend ActiveBackend();

// "portable" or "AVX-512".
const char* BackendName(Backend backend);

// true: the portable backend even where the AVX-512 one could run (tests and A/B comparisons);
// false: back to the choice above. Process-wide; do not flip it while kernels run on other threads.
void UsePortableKernels(bool on);

}  // namespace motionfork::kernels
