#include "denoise/outlier_repair.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/text_format.h"
#include "denoise/motion_filters.h"

namespace motionfork {

std::string DescribeOutlierRepair(const OutlierRepair& r) {
  if (!r.enabled()) return "none";
  return StringPrintf("%s over +-%d frames at %.3g deviations",
                      r.trend ? "Hampel test about the Theil-Sen line" : "Hampel test",
                      r.half_window, r.deviations);
}

namespace {

// Per value [T, J, 3]: 1 where the value is farther from the Theil-Sen line through the window of
// its coordinate centred on it (the median of the pairwise slopes; the median offset) than
// `deviations` x 1.4826 x the median absolute distance of the window's values from that line.
std::vector<uint8_t> TrendOutliers(const std::vector<float>& p, int joints, int half,
                                   double deviations) {
  const size_t F = 3 * static_cast<size_t>(std::max(joints, 0));
  if (joints < 1 || p.size() % F != 0) {
    throw std::invalid_argument("OutlierJoints: expected frames x " + std::to_string(joints) +
                                " joints x 3 values, got " + std::to_string(p.size()));
  }
  const int T = static_cast<int>(p.size() / F);
  std::vector<uint8_t> flags(p.size(), 0);
  std::vector<double> slopes, offsets;
  for (size_t v = 0; v < F; ++v) {
    const auto x = [&](int t) { return static_cast<double>(p[static_cast<size_t>(t) * F + v]); };
    for (int t = 0; t < T; ++t) {
      const int a = std::max(0, t - half), b = std::min(T - 1, t + half);
      if (b - a < 2) continue;
      slopes.clear();
      for (int i = a; i <= b; ++i)
        for (int k = i + 1; k <= b; ++k) slopes.push_back((x(k) - x(i)) / (k - i));
      const double slope = MedianInPlace(&slopes);
      offsets.clear();
      for (int i = a; i <= b; ++i) offsets.push_back(x(i) - slope * (i - t));
      const double offset = MedianInPlace(&offsets);
      for (double& o : offsets) o = std::abs(o - offset);
      const double scale = 1.4826 * MedianInPlace(&offsets);
      if (std::abs(x(t) - offset) > deviations * scale) flags[static_cast<size_t>(t) * F + v] = 1;
    }
  }
  return flags;
}

}  // namespace

std::vector<uint8_t> OutlierJoints(const std::vector<float>& motion, int joints,
                                   const OutlierRepair& repair) {
  std::vector<float> medians;
  const std::vector<uint8_t> values =
      repair.trend
          ? TrendOutliers(motion, joints, repair.half_window, repair.deviations)
          : HampelOutliers(motion, joints, repair.half_window, repair.deviations, &medians);
  std::vector<uint8_t> flags(values.size() / 3, 0);
  for (size_t i = 0; i < values.size(); ++i)
    if (values[i]) flags[i / 3] = 1;
  return flags;
}

std::vector<float> RepairOutliers(const std::vector<float>& motion, int joints,
                                  const OutlierRepair& repair, int* repaired) {
  if (repaired) *repaired = 0;
  if (!repair.enabled()) return motion;
  const std::vector<uint8_t> flags = OutlierJoints(motion, joints, repair);
  const int T = static_cast<int>(flags.size() / joints);
  std::vector<float> out = motion;
  for (int j = 0; j < joints; ++j) {
    auto flagged = [&](int t) { return flags[static_cast<size_t>(t) * joints + j] != 0; };
    int before = -1;  // the last unflagged frame so far
    for (int t = 0; t < T; ++t) {
      if (!flagged(t)) {
        before = t;
        continue;
      }
      int after = t + 1;
      while (after < T && flagged(after)) ++after;
      if (before < 0 && after >= T) break;  // every frame flagged: left as it is
      for (int u = t; u < after; ++u) {
        for (int d = 0; d < 3; ++d) {
          const auto at = [&](int frame) {
            return motion[(static_cast<size_t>(frame) * joints + j) * 3 + d];
          };
          float v;
          if (before < 0) {
            v = at(after);
          } else if (after >= T) {
            v = at(before);
          } else {
            const double w = static_cast<double>(u - before) / (after - before);
            v = static_cast<float>((1 - w) * at(before) + w * at(after));
          }
          out[(static_cast<size_t>(u) * joints + j) * 3 + d] = v;
        }
      }
      if (repaired) *repaired += after - t;
      t = after - 1;
    }
  }
  return out;
}

}  // namespace motionfork
