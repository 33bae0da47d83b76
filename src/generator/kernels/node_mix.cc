// node_mix.h's entry points: the AVX-512 backend, or an error where it does not run.
#include "generator/kernels/node_mix.h"

#include <stdexcept>

#include "generator/kernels/backend.h"
#include "generator/kernels/backends.h"

namespace motionfork::kernels {

namespace {
[[noreturn]] void NoBackend() {
  throw std::logic_error(
      "kernels::NodeMix needs the AVX-512 backend (ActiveBackend()); use a matrix product");
}
}  // namespace

void NodeMix(const float* a, int64_t nodes, const float* s, int64_t ld, int64_t j0, int64_t j1,
             float* y) {
#ifdef MOTIONFORK_KERNELS_AVX512
  if (ActiveBackend() == Backend::kAvx512) return avx512::NodeMix(a, nodes, s, ld, j0, j1, y);
#endif
  NoBackend();
}

void NodeMixBackward(const float* at, int64_t nodes, const float* g, const float* s, int64_t ld,
                     int64_t j0, int64_t j1, float* gs, float* ga) {
#ifdef MOTIONFORK_KERNELS_AVX512
  if (ActiveBackend() == Backend::kAvx512)
    return avx512::NodeMixBackward(at, nodes, g, s, ld, j0, j1, gs, ga);
#endif
  NoBackend();
}

}  // namespace motionfork::kernels
