// The CPU's instruction-set extensions, probed once per process. Everything that chooses code by
// CPU asks here (the kernels' backend, backend.h; OpenBLAS's kernel choice,
// torch_util/blas_core.h), so all of them agree. Plain C++: usable before main() and without
// LibTorch.
#pragma once

namespace motionfork::kernels {

struct CpuFeatures {
  bool avx = false;          // AVX, with the OS saving the wider registers
  bool avx2_fma = false;     // AVX2 and FMA
  bool avx512 = false;       // AVX-512 F, DQ, BW and VL (the AVX-512 kernels need all four)
  bool avx512_bf16 = false;  // and AVX512-BF16 (vdpbf16ps, bf16_product.h)
};

// Probed on first use (thread-safe), then cached. All false on CPUs other than x86.
const CpuFeatures& Cpu();

}  // namespace motionfork::kernels
