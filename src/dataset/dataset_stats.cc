#include "dataset/dataset_stats.h"

#include <algorithm>

#include "dataset/windows.h"

namespace motionfork {

DatasetStats ComputeDatasetStats(const Dataset& ds) {
  const ProtocolOptions& p = ds.protocol;
  DatasetStats stats;
  for (const Clip& c : ds.clips) {
    SplitStats& s = c.split == Split::kTrain ? stats.train : stats.test;
    const int T = c.motion.num_frames();
    s.clips_listed++;
    s.usable++;
    s.frames += T;
    s.test_windows += CountSlidingWindows(T, p.window_length(), p.test_stride, p.test_include_last);
    s.train_windows += std::max(0, T - p.window_length() + 1);
  }
  for (const SkippedClip& c : ds.skipped) {
    if (c.split.empty()) {
      stats.skipped_unsplit[c.reason]++;
      continue;
    }
    SplitStats& s = c.split == "train" ? stats.train : stats.test;
    s.clips_listed++;
    s.skipped[c.reason]++;
  }
  for (const auto& group : ds.groups) stats.clips += group.second;
  return stats;
}

}  // namespace motionfork
