// What a protocol makes of a data folder: clips, frames and windows per split, and why clips were
// skipped (`motionfork dataset stats`).
#pragma once

#include <map>
#include <string>

#include "dataset/dataset.h"

namespace motionfork {

struct SplitStats {
  int clips_listed = 0;  // clips the split assigns here (usable or skipped)
  int usable = 0;
  long long frames = 0;
  long long test_windows = 0;          // the protocol's test windows (stride, include-last rule)
  long long train_windows = 0;         // every start
  std::map<std::string, int> skipped;  // reason -> clips
};

struct DatasetStats {
  SplitStats train, test;
  std::map<std::string, int> skipped_unsplit;  // reason -> clips no split names
  int clips = 0;                               // read from every source
};

DatasetStats ComputeDatasetStats(const Dataset& dataset);

}  // namespace motionfork
