// Runs the built motionfork command as a user would (stdout and stderr together, exit status).
#pragma once

#include <sys/wait.h>

#include <array>
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>

namespace motionfork::testing {

struct Run {
  int status;
  std::string output;  // stdout and stderr
};

// A shell command line's exit status and output (add "2>&1" to capture stderr too).
inline Run RunShell(const std::string& command) {
  Run r{0, ""};
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe);
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int st = pclose(pipe);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// `binary --cache-dir none ARGS`, stdout and stderr together.
inline Run RunMotionfork(const std::string& binary, const std::string& args) {
  return RunShell(binary + " --cache-dir none " + args + " 2>&1");
}

#ifdef MOTIONFORK_BINARY
inline Run Motionfork(const std::string& args) { return RunMotionfork(MOTIONFORK_BINARY, args); }
#endif

}  // namespace motionfork::testing
