#include "torch_util/blas_core.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "generator/kernels/cpu_features.h"

// OpenBLAS's C entry point (libopenblas), weak: absent when another BLAS is linked.
extern "C" char* openblas_get_corename(void) __attribute__((weak));

namespace motionfork {

std::string BlasCoreName() {
  if (!openblas_get_corename) return "";
  const char* name = openblas_get_corename();
  return name ? name : "";
}

std::string BetterBlasCore() {
  if (std::getenv("OPENBLAS_CORETYPE")) return "";
  std::string core = BlasCoreName();
  if (core.empty()) return "";
  std::transform(core.begin(), core.end(), core.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  // OpenBLAS's fallbacks for Intel CPUs it does not recognise: pre-AVX kernels.
  static const char* const kGeneric[] = {"prescott",  "core2",  "penryn", "dunnington",
                                         "nehalem",   "atom",   "katmai", "coppermine",
                                         "northwood", "banias", "unknown"};
  if (std::find(std::begin(kGeneric), std::end(kGeneric), core) == std::end(kGeneric)) return "";
  const kernels::CpuFeatures& cpu = kernels::Cpu();  // the one probe (OS support included)
  if (cpu.avx512) return "SkylakeX";
  if (cpu.avx2_fma) return "Haswell";
  if (cpu.avx) return "SandyBridge";
  return "";
}

void UseFastBlasKernels(char** argv) {
  if (const char* off = std::getenv("MOTIONFORK_BLAS_REEXEC"); off && std::string(off) == "0")
    return;
  const std::string core = BetterBlasCore();
  if (core.empty()) return;
  setenv("OPENBLAS_CORETYPE", core.c_str(), 1);  // also stops a second re-exec
  execv("/proc/self/exe", argv);
  // exec failed (no /proc?): carry on with the kernels we have.
}

}  // namespace motionfork
