// One core's peak float32 multiply-add rate with AVX-512, measured (bench_fma_peak,
// bench_generator): twelve independent chains of 16-wide fused multiply-adds on registers only,
// so only the core's FMA units and its clock at that moment limit it. GFLOP/s, 2 per multiply-add.
#pragma once

#include <chrono>
#include <cstdio>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace motionfork::bench {

#if defined(__x86_64__) || defined(__i386__)
// Requires AVX-512 F (check kernels::Cpu().avx512 first, generator/kernels/cpu_features.h).
__attribute__((target("avx512f"))) inline double PeakGflops(long iterations) {
  constexpr int kChains = 12;  // enough independent chains to cover the FMA latency on two units
  // Different starting values: identical chains would be merged into one by the compiler.
  __m512 a[kChains];
#pragma GCC unroll 12
  for (int j = 0; j < kChains; ++j) a[j] = _mm512_set1_ps(1.0f + 0.1f * j);
  const __m512 b = _mm512_set1_ps(0.9999999f), c = _mm512_set1_ps(1e-7f);
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < iterations; ++i) {
#pragma GCC unroll 12
    for (int j = 0; j < kChains; ++j) a[j] = _mm512_fmadd_ps(a[j], b, c);
    __asm__ volatile("");  // keep the loop: one iteration = 12 multiply-adds of 16 lanes
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  __m512 sum = a[0];
  for (int j = 1; j < kChains; ++j) sum = _mm512_add_ps(sum, a[j]);
  if (_mm512_reduce_add_ps(sum) < 0) std::printf("unreachable\n");  // the result is used
  return iterations * kChains * 16.0 * 2 / seconds / 1e9;
}

// The same for AVX512-BF16's vdpbf16ps (two multiply-adds per 32-bit lane, bf16 inputs, float32
// sums): 4 FLOP per lane and instruction. Requires AVX512-BF16 (kernels::Cpu().avx512_bf16).
__attribute__((target("avx512f,avx512bf16"))) inline double PeakBf16Gflops(long iterations) {
  constexpr int kChains = 12;
  __m512 a[kChains];
#pragma GCC unroll 12
  for (int j = 0; j < kChains; ++j) a[j] = _mm512_set1_ps(1.0f + 0.1f * j);
  const __m512bh b = _mm512_cvtne2ps_pbh(_mm512_set1_ps(1e-3f), _mm512_set1_ps(1e-3f));
  const __m512bh c = _mm512_cvtne2ps_pbh(_mm512_set1_ps(0.5f), _mm512_set1_ps(0.5f));
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < iterations; ++i) {
#pragma GCC unroll 12
    for (int j = 0; j < kChains; ++j) a[j] = _mm512_dpbf16_ps(a[j], b, c);
    __asm__ volatile("");
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  __m512 sum = a[0];
  for (int j = 1; j < kChains; ++j) sum = _mm512_add_ps(sum, a[j]);
  if (_mm512_reduce_add_ps(sum) < 0) std::printf("unreachable\n");
  return iterations * kChains * 16.0 * 4 / seconds / 1e9;
}
#else
inline double PeakGflops(long) { return 0; }  // no AVX-512 off x86
inline double PeakBf16Gflops(long) { return 0; }
#endif

}  // namespace motionfork::bench
