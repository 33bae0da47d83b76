// One core's peak float32 multiply-add rate with AVX-512, measured (bench_fma_peak,
// bench_generator): twelve independent chains of 16-wide fused multiply-adds on registers only,
// so only the core's FMA units and its clock at that moment limit it. GFLOP/s, 2 per multiply-add.
#pragma once

#include <immintrin.h>

#include <chrono>
#include <cstdio>

namespace motionfork::bench {

// Requires AVX-512 F (check __builtin_cpu_supports("avx512f") first).
__attribute__((target("avx512f"))) inline double PeakGflops(long iterations) {
  // Different starting values: identical chains would be merged into one by the compiler.
  __m512 a0 = _mm512_set1_ps(1.0f), a1 = _mm512_set1_ps(1.1f), a2 = _mm512_set1_ps(1.2f),
         a3 = _mm512_set1_ps(1.3f), a4 = _mm512_set1_ps(1.4f), a5 = _mm512_set1_ps(1.5f),
         a6 = _mm512_set1_ps(1.6f), a7 = _mm512_set1_ps(1.7f), a8 = _mm512_set1_ps(1.8f),
         a9 = _mm512_set1_ps(1.9f), a10 = _mm512_set1_ps(2.0f), a11 = _mm512_set1_ps(2.1f);
  const __m512 b = _mm512_set1_ps(0.9999999f), c = _mm512_set1_ps(1e-7f);
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < iterations; ++i) {
    a0 = _mm512_fmadd_ps(a0, b, c);
    a1 = _mm512_fmadd_ps(a1, b, c);
    a2 = _mm512_fmadd_ps(a2, b, c);
    a3 = _mm512_fmadd_ps(a3, b, c);
    a4 = _mm512_fmadd_ps(a4, b, c);
    a5 = _mm512_fmadd_ps(a5, b, c);
    a6 = _mm512_fmadd_ps(a6, b, c);
    a7 = _mm512_fmadd_ps(a7, b, c);
    a8 = _mm512_fmadd_ps(a8, b, c);
    a9 = _mm512_fmadd_ps(a9, b, c);
    a10 = _mm512_fmadd_ps(a10, b, c);
    a11 = _mm512_fmadd_ps(a11, b, c);
    __asm__ volatile("");  // keep the loop: one iteration = 12 multiply-adds of 16 lanes
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const __m512 sum = _mm512_add_ps(
      _mm512_add_ps(_mm512_add_ps(_mm512_add_ps(a0, a1), _mm512_add_ps(a2, a3)),
                    _mm512_add_ps(_mm512_add_ps(a4, a5), _mm512_add_ps(a6, a7))),
      _mm512_add_ps(_mm512_add_ps(a8, a9), _mm512_add_ps(a10, a11)));
  if (_mm512_reduce_add_ps(sum) < 0) std::printf("unreachable\n");  // the result is used
  return iterations * 12.0 * 16 * 2 / seconds / 1e9;
}

}  // namespace motionfork::bench
