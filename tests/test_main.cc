// One Catch2 main for every test executable. Tests run with OpenBLAS's fast kernels, as the
// programs do (torch_util/blas_core.h).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "torch_util/blas_core.h"

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  return Catch::Session().run(argc, argv);
}
