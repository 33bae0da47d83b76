#include "generator/kernels/precision.h"

#include <stdexcept>

#include "generator/kernels/bf16_product.h"

namespace motionfork {

Precision ParsePrecision(const std::string& text) {
  if (text == "fp32") return Precision::kFp32;
  if (text == "bf16") return Precision::kBf16;
  if (text == "auto") return Precision::kAuto;
  throw std::invalid_argument("precision: expected fp32, bf16 or auto, got '" + text + "'");
}

const char* PrecisionName(Precision p) {
  switch (p) {
    case Precision::kFp32:
      return "fp32";
    case Precision::kBf16:
      return "bf16";
    case Precision::kAuto:
      break;
  }
  return "auto";
}

bool Bf16ProductsAvailable() { return kernels::Bf16KernelRuns(); }

Precision ResolvePrecision(Precision p) {
  if (p == Precision::kAuto) return Bf16ProductsAvailable() ? Precision::kBf16 : Precision::kFp32;
  if (p == Precision::kBf16 && !Bf16ProductsAvailable()) {
    throw std::invalid_argument(std::string("precision bf16: ") +
                                (kernels::Bf16KernelBuilt()
                                     ? "this CPU has no AVX512-BF16 (avx512_bf16 in /proc/cpuinfo)"
                                     : "this build has no AVX512-BF16 kernel") +
                                "; expected fp32 or auto here");
  }
  return p;
}

}  // namespace motionfork
