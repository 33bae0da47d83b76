// Shared by the bf16 tests: whether the AVX512-BF16 kernel runs here, else a visible skip.
#pragma once

#include <cstdlib>
#include <string>

#include "generator/kernels/bf16_product.h"
#include "generator/kernels/cpu_features.h"
#include "torch_catch.h"  // Catch after LibTorch (glog's CHECK dropped)

namespace motionfork::testing {

// True when the AVX512-BF16 kernel runs; else WARNs "SKIPPED: ..." (CTest shows a skip) ending in
// `instead` (what the test checks in its place) and returns false. MOTIONFORK_REQUIRE_BF16=1 makes
// a CPU without AVX512-BF16 a failure.
inline bool Bf16OrSkip(const std::string& instead) {
  if (!kernels::Bf16KernelBuilt()) {
    WARN("SKIPPED: this build has no AVX512-BF16 kernel; " + instead);
    return false;
  }
  if (!kernels::Cpu().avx512_bf16) {
    if (const char* need = std::getenv("MOTIONFORK_REQUIRE_BF16"); need && *need == '1')
      FAIL("MOTIONFORK_REQUIRE_BF16=1 but this CPU has no AVX512-BF16");
    WARN("SKIPPED: this CPU has no AVX512-BF16; " + instead);
    return false;
  }
  REQUIRE(kernels::Bf16KernelRuns());
  return true;
}

}  // namespace motionfork::testing
