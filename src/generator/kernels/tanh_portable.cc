// The portable tanh: the AVX-512 backend's algorithm (tanh_avx512.inc) one float at a time, in
// code the compiler vectorises at the default flags (no calls, no branches, no float-to-integer
// conversion).
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "generator/kernels/backends.h"

namespace motionfork::kernels::portable {

namespace {

// tanh(x) = 1 - 2 / (2^t + 1), t = 2x log2(e) = n + f (n the nearest integer, |f| <= 1/2):
// 2^f by tanh_avx512.inc's polynomial, 2^n by building the float's exponent field.
inline float TanhOne(float x) {
  // x clamped to [-9, 9] (tanh is within 3e-8 of +-1 beyond), NaN kept. On the float's bits: GCC
  // does not vectorise a loop with a float comparison followed by arithmetic (-ftrapping-math).
  int32_t bits;
  std::memcpy(&bits, &x, sizeof(bits));
  const int32_t magnitude = bits & INT32_MAX, nine = 0x41100000;  // 9.0f
  const int32_t clamped = magnitude > 0x7F800000 ? magnitude : std::min(magnitude, nine);
  bits = (bits & INT32_MIN) | clamped;
  std::memcpy(&x, &bits, sizeof(x));
  const float t = x * 2.88539008177792681f;
  const float magic = 12582912.0f;  // 1.5 * 2^23: adding it rounds to an integer
  const float r = t + magic;
  const float n = r - magic;
  const float f = t - n;
  float p = 0.001327647129073739f;
  p = p * f + 0.009675541892647743f;
  p = p * f + 0.05550713092088699f;
  p = p * f + 0.24022120237350464f;
  p = p * f + 0.6931469440460205f;
  p = p * f + 1.0000001192092896f;
  // r's low mantissa bits hold n: 2^n's bits are (n + 127) << 23.
  int32_t rb;
  std::memcpy(&rb, &r, sizeof(rb));
  const uint32_t eb = static_cast<uint32_t>(rb - 0x4B400000 + 127) << 23;
  float two_n;
  std::memcpy(&two_n, &eb, sizeof(two_n));
  return 1.0f - 2.0f / (p * two_n + 1.0f);
}

}  // namespace

void Tanh(float* x, int64_t n) {
  for (int64_t i = 0; i < n; ++i) x[i] = TanhOne(x[i]);
}

}  // namespace motionfork::kernels::portable
