// What the experiment subcommands read, loaded from an app: a protocol's dataset (with a progress
// bar and the cache folder) and a forecaster for the downstream figures.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "commands.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "eval/history_forecasting.h"

namespace motionfork::app {

// split_file: overrides the protocol's split file ("" = the protocol's).
Dataset LoadDatasetWithProgress(const ProtocolOptions& protocol, const SkeletonConfig& skeleton,
                                const std::string& data_dir, const std::string& split_file,
                                const GlobalOptions& global);
// The same from a protocol name or path (looked up in the configs folder).
Dataset LoadProtocolDataset(const std::string& protocol, const std::string& data_dir,
                            const std::string& split_file, const GlobalOptions& global);

// A generator bundle as the experiments' forecaster: K futures per history, the network's raw
// output (the history is what differs, and the angle-range repair's cost grows with every
// implausible, e.g. mean-filled, history). dir "" = none (forecast left empty).
HistoryForecaster LoadHistoryForecaster(const std::string& dir, int k, uint64_t seed);

// The forecasting figures as JSON; setting_key names each setting, before/after suffix its ADE
// and FDE keys (e.g. "occlusion", "mean_imputed", "hgvae_imputed").
nlohmann::ordered_json ForecastingJson(const ForecastingFigures& f, const std::string& setting_key,
                                       const std::string& before, const std::string& after);

}  // namespace motionfork::app
