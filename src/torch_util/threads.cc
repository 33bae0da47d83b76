#include "torch_util/threads.h"

#include <sched.h>
#include <sys/syscall.h>
#include <torch/torch.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
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

namespace {

// The kernel's struct sched_attr, first version (linux/sched/types.h clashes with glibc's
// sched.h).
struct SchedAttr {
  uint32_t size;
  uint32_t sched_policy;
  uint64_t sched_flags;
  int32_t sched_nice;
  uint32_t sched_priority;
  uint64_t sched_runtime, sched_deadline, sched_period;
};

}  // namespace

int ShortenHelperThreadSlices() {
  const pid_t self = static_cast<pid_t>(syscall(SYS_gettid));
  int changed = 0;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task", error)) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t tid = static_cast<pid_t>(std::stol(name));
    if (tid == self) continue;
    SchedAttr attr{};
    attr.size = sizeof(attr);
    attr.sched_policy = SCHED_OTHER;
    attr.sched_runtime = 100000;  // ns: the shortest slice the kernel accepts
    // (Older kernels ignore the runtime of a fair-scheduled thread; failures change nothing.)
    if (syscall(SYS_sched_setattr, tid, &attr, 0u) == 0) ++changed;
  }
  return changed;
}

}  // namespace motionfork
