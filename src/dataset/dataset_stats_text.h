// `motionfork dataset stats`'s report as text for people: what a protocol makes of a data folder
// (dataset_stats.h). The same as JSON: dataset_stats_json.h.
#pragma once

#include <string>

#include "dataset/dataset.h"
#include "dataset/dataset_stats.h"

namespace motionfork {

// The protocol's timing, the sources, clips, frames and windows per split, skipped clips and
// split-file names not found. data_dir: as the user named it; split_file_given: a split file
// (the protocol's or the user's) chose the split rather than the subjects.
std::string DatasetStatsText(const Dataset& dataset, const DatasetStats& stats,
                             const std::string& data_dir, bool split_file_given);

}  // namespace motionfork
