#include "generator/kernels/backend.h"

#include <atomic>

#include "generator/kernels/cpu_features.h"

namespace motionfork::kernels {

namespace {
std::atomic<bool> force_portable{false};
}  // namespace

bool Avx512Built() {
#ifdef MOTIONFORK_KERNELS_AVX512  // CMakeLists.txt: set when the *_avx512.cc files are compiled
  return true;
#else
  return false;
#endif
}

Backend ActiveBackend() {
  static const bool avx512 = Avx512Built() && Cpu().avx512;
  return avx512 && !force_portable.load(std::memory_order_relaxed) ? Backend::kAvx512
                                                                   : Backend::kPortable;
}

const char* BackendName(Backend backend) {
  return backend == Backend::kAvx512 ? "AVX-512" : "portable";
}

void UsePortableKernels(bool on) { force_portable = on; }

}  // namespace motionfork::kernels
