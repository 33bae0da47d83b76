// `motionfork dataset stats`'s report as JSON: what a protocol makes of a data folder
// (dataset_stats.h).
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "dataset/dataset.h"
#include "dataset/dataset_stats.h"

namespace motionfork {

// The protocol's timing, clips per source, and clips, frames and windows per split.
nlohmann::ordered_json DatasetStatsJson(const Dataset& dataset, const DatasetStats& stats);

}  // namespace motionfork
