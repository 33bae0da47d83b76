// Runs a reader in a child process whose address space is capped (RLIMIT_AS, 1 GiB by default), so
// a reader that allocates for what a file claims rather than for the bytes it holds fails the test
// with kOutOfMemory instead of taking the machine's memory.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <new>
#include <string>

#include "core/error.h"

namespace motionfork::testing {

enum class LimitedOutcome { kRead, kFormatError, kOutOfMemory, kOtherError, kCrashed };

struct LimitedRun {
  LimitedOutcome outcome;
  std::string message;  // the exception's message
};

inline LimitedRun RunWithMemoryLimit(const std::function<void()>& read,
                                     rlim_t bytes = rlim_t{1} << 30) {
  int fds[2];
  if (pipe(fds) != 0) return {LimitedOutcome::kCrashed, "pipe failed"};
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_AS, &limit);
    LimitedOutcome outcome = LimitedOutcome::kRead;
    std::string message;
    try {
      read();
    } catch (const FormatError& e) {
      outcome = LimitedOutcome::kFormatError;
      message = e.what();
    } catch (const std::bad_alloc& e) {
      outcome = LimitedOutcome::kOutOfMemory;
      message = e.what();
    } catch (const std::exception& e) {
      outcome = LimitedOutcome::kOtherError;
      message = e.what();
    }
    if (write(fds[1], message.data(), message.size()) < 0) outcome = LimitedOutcome::kCrashed;
    close(fds[1]);
    _exit(static_cast<int>(outcome));
  }
  close(fds[1]);
  std::string message;
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof(buf))) > 0;) message.append(buf, n);
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status)) return {LimitedOutcome::kCrashed, message};
  return {static_cast<LimitedOutcome>(WEXITSTATUS(status)), message};
}

}  // namespace motionfork::testing
