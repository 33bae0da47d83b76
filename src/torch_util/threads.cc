#include "torch_util/threads.h"

#include <torch/torch.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "launch/worker_place.h"

// OpenBLAS's C entry point (libopenblas); declared here to avoid depending on its header layout.
extern "C" void openblas_set_num_threads(int num_threads) __attribute__((weak));

namespace motionfork {

void PinThreads(int threads) {
  if (threads < 1) {
    throw std::invalid_argument("PinThreads: expected >= 1 thread, got " + std::to_string(threads));
  }
  torch::set_num_threads(threads);
  static bool interop_set = false;
  if (!interop_set) {
    try {
      torch::set_num_interop_threads(threads);
    } catch (const c10::Error&) {
      // Already started: keep the pool as it is.
    }
    interop_set = true;
  }
  if (openblas_set_num_threads) openblas_set_num_threads(threads);
}

int WindowThreads(int requested) {
  PinThreads(1);
  return requested > 0 ? requested : CoresAvailable();
}

int DefaultThreads() {
  if (const char* env = std::getenv("MOTIONFORK_THREADS"); env && *env) {
    const int n = std::atoi(env);
    if (n >= 1) return n;
  }
  return 1;
}

}  // namespace motionfork
