// Benchmark: one core's peak float32 multiply-add rate with AVX-512 (the reference the generator's
// GFLOP/s are compared with in BENCHMARKS.md).
//
//   bench_fma_peak
//
// Twelve independent chains of 16-wide fused multiply-adds on registers only (no memory), so
// only the core's two FMA units and its clock limit it. Prints GFLOP/s (2 per multiply-add).
#include "fma_peak.h"

#include <cstdio>

#include "generator/kernels/cpu_features.h"

int main() {
  if (!motionfork::kernels::Cpu().avx512) {
    std::printf("this CPU has no AVX-512: nothing to measure\n");
    return 0;
  }
  motionfork::bench::PeakGflops(20000000);  // warm up (clock ramp)
  for (int run = 0; run < 3; ++run)
    std::printf("AVX-512 FMA peak, one core: %.1f GFLOP/s\n",
                motionfork::bench::PeakGflops(200000000));
  return 0;
}
