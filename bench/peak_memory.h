// The process's peak resident memory (VmHWM of /proc/self/status), for the benchmarks.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace motionfork::bench {

// MB; 0 where /proc/self/status cannot be read.
inline double PeakResidentMegabytes() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  double kb = 0;
  while (std::fgets(line, sizeof line, f)) {
    if (!std::strncmp(line, "VmHWM:", 6)) kb = std::atof(line + 6);
  }
  std::fclose(f);
  return kb / 1024;
}

}  // namespace motionfork::bench
