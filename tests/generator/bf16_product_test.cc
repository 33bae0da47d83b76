// bf16 products with float32 sums (generator/kernels/bf16_product.h): rounding, packing, the
// portable kernel everywhere and the AVX512-BF16 kernel where the CPU has it.
#include "generator/kernels/bf16_product.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "bf16_skip.h"
#include "generator/kernels/backend.h"
#include "generator/kernels/cpu_features.h"
#include "torch_catch.h"

using namespace motionfork;

namespace {

bool Bf16OrSkip() { return testing::Bf16OrSkip("the portable kernel is tested"); }

// Every shape: the kernel's Z against the exact product of the bf16-rounded inputs (in double) and
// against the float32 product within bf16's rounding (2^-8 relative per input, of sum |x||w|).
void CheckShapes() {
  for (int64_t m : {1, 7, 8, 13, 40}) {
    for (int64_t kk : {1, 2, 7, 30, 256, 1029, 2100}) {
      for (int64_t cols : {1, 16, 30, 48, 64, 100}) {
        const int64_t ldx = kk + 3;  // rows of X not adjacent
        std::vector<float> x(m * ldx, std::numeric_limits<float>::quiet_NaN()), w(kk * cols);
        for (int64_t r = 0; r < m; ++r)
          for (int64_t i = 0; i < kk; ++i) x[r * ldx + i] = std::sin(0.37f * (r * kk + i)) * 1.7f;
        for (size_t i = 0; i < w.size(); ++i) w[i] = std::cos(0.11f * i) * 0.3f;
        const kernels::PackedWeightBf16 pw = kernels::PackWeightBf16(w.data(), kk, cols);
        kernels::AlignedFloats z(m * pw.padded);
        kernels::MatMulBf16(x.data(), m, ldx, pw, z.get());
        double worst_rounded = 0, worst_exact = 0;
        for (int64_t r = 0; r < m; ++r) {
          for (int64_t c = 0; c < pw.padded; ++c) {
            double rounded = 0, exact = 0, scale = 0;
            for (int64_t i = 0; c < cols && i < kk; ++i) {
              const double a = x[r * ldx + i], b = w[i * cols + c];
              rounded += double(kernels::RoundToBf16(x[r * ldx + i])) *
                         kernels::RoundToBf16(w[i * cols + c]);
              exact += a * b;
              scale += std::abs(a * b);
            }
            const double got = z.get()[r * pw.padded + c];
            worst_rounded = std::max(worst_rounded, std::abs(got - rounded) / (1 + scale));
            worst_exact = std::max(worst_exact, std::abs(got - exact) / (1e-30 + scale + 1e-6));
          }
        }
        INFO("m " << m << " k " << kk << " cols " << cols);
        CHECK(worst_rounded < 1e-5);      // only the float32 sums' order differs
        CHECK(worst_exact < 2 * 0x1p-8);  // two roundings of 2^-9 each, at most
      }
    }
  }
}

}  // namespace

TEST_CASE("bf16 rounding: nearest, ties to even, NaN and infinity kept") {
  CHECK(kernels::RoundToBf16(1.0f) == 1.0f);
  CHECK(kernels::RoundToBf16(1.0f + 0x1p-8f) == 1.0f);                       // tie: to even (1.0)
  CHECK(kernels::RoundToBf16(1.0f + 3 * 0x1p-8f) == 1.0f + 0x1p-6f);         // tie: to even (up)
  CHECK(kernels::RoundToBf16(1.0f + 0x1p-8f + 0x1p-12f) == 1.0f + 0x1p-7f);  // above a tie: up
  CHECK(kernels::RoundToBf16(-2.5f) == -2.5f);
  CHECK(kernels::Bf16Bits(1.0f) == 0x3F80);
  CHECK(std::isnan(kernels::RoundToBf16(std::numeric_limits<float>::quiet_NaN())));
  CHECK(std::isinf(kernels::RoundToBf16(std::numeric_limits<float>::infinity())));
  CHECK(kernels::RoundToBf16(3.0e38f) == Approx(3.0e38f).epsilon(0x1p-8));         // near bf16 max
  CHECK(kernels::RoundToBf16(3.4e38f) == std::numeric_limits<float>::infinity());  // overflows
}

TEST_CASE("bf16 weights are packed in pairs of rows, an odd last row padded with zeros") {
  const std::vector<float> w = {1, 2, 3, 4, 5, 6};  // [3, 2]
  const kernels::PackedWeightBf16 p = kernels::PackWeightBf16(w.data(), 3, 2);
  CHECK(p.pairs == 2);
  CHECK(p.padded == 16);
  // Panel of 16 columns: pair 0 = rows 0 and 1, pair 1 = row 2 and zeros.
  CHECK(p.values[0] == (uint32_t(kernels::Bf16Bits(1)) | uint32_t(kernels::Bf16Bits(3)) << 16));
  CHECK(p.values[1] == (uint32_t(kernels::Bf16Bits(2)) | uint32_t(kernels::Bf16Bits(4)) << 16));
  CHECK(p.values[2] == 0);  // a padded column
  CHECK(p.values[16] == kernels::Bf16Bits(5));
  CHECK(p.values[17] == kernels::Bf16Bits(6));
}

TEST_CASE("bf16 product: portable kernel, every shape") {
  kernels::UsePortableKernels(true);
  CheckShapes();
  kernels::UsePortableKernels(false);
}

TEST_CASE("bf16 product: AVX512-BF16 kernel, every shape") {
  if (!Bf16OrSkip()) return;
  CheckShapes();
}
