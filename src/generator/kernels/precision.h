// Which arithmetic the generator's products run in (issue 30), as `--precision` and the C++ API's
// LoadOptions::precision name it:
//   fp32  float32 products everywhere (the default of training and of a Forecaster as built);
//   bf16  the hidden layers' products with bfloat16 inputs and float32 sums (fused_generator.h),
//         on the AVX512-BF16 kernel; an error on a CPU without AVX512-BF16;
//   auto  bf16 where the CPU has AVX512-BF16, fp32 elsewhere: the default of `predict`, `eval`,
//         the C++ API's LoadOptions and Python's Model.load.
// Measured accuracy of bf16 against fp32 (same seed): RESULTS.md "bf16 products".
#pragma once

#include <string>

namespace motionfork {

enum class Precision { kFp32, kBf16, kAuto };

// "fp32", "bf16" or "auto"; anything else: std::invalid_argument naming what was given.
Precision ParsePrecision(const std::string& text);
const char* PrecisionName(Precision p);

// Whether the bf16 products run on this CPU and build (the AVX512-BF16 kernel).
bool Bf16ProductsAvailable();

// kBf16 or kFp32 for this CPU: kAuto resolves to kBf16 where Bf16ProductsAvailable(), kBf16 there
// only (std::invalid_argument naming the missing feature elsewhere).
Precision ResolvePrecision(Precision p);

}  // namespace motionfork
