#include "refine/refiner_options.h"

#include <algorithm>
#include <stdexcept>

namespace motionfork {

int RefinerOptions::reach() const {
  int r = 1;
  for (int d : dilations) r += d;
  return std::max(r, linear_reach);
}

void ValidateRefinerOptions(const RefinerOptions& o, const std::string& what) {
  if (o.channels < 0 || o.channels > 4096)
    throw std::invalid_argument(what + ": expected 0 <= channels <= 4096, got " +
                                std::to_string(o.channels));
  if (!o.enabled()) return;
  if (o.window < 2 || o.stride < 1 || o.stride > o.window)
    throw std::invalid_argument(what + ": expected window >= 2 and 1 <= stride <= window, got " +
                                std::to_string(o.window) + " and " + std::to_string(o.stride));
  if (o.dilations.empty()) throw std::invalid_argument(what + ": expected at least one dilation");
  if (o.linear_reach < 0 || o.linear_reach > 1024)
    throw std::invalid_argument(what + ": expected 0 <= linear_reach <= 1024, got " +
                                std::to_string(o.linear_reach));
  for (int d : o.dilations) {
    if (d < 1 || d > 1024)
      throw std::invalid_argument(what + ": expected dilations in 1..1024, got " +
                                  std::to_string(d));
  }
}

}  // namespace motionfork
