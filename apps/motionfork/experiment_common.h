// What the subcommands that run on a protocol's data share: its dataset, loaded with a progress bar
// and the cache folder, and the rows of the forecasting figures from repaired histories.
#pragma once

#include <string>

#include "commands.h"
#include "dataset/dataset.h"
#include "eval/history_forecasting.h"

namespace motionfork::app {

// protocol: a name or path (looked up in the configs folder); split_file overrides the protocol's
// split file ("" = the protocol's).
Dataset LoadProtocolDataset(const std::string& protocol, const std::string& data_dir,
                            const std::string& split_file, const GlobalOptions& global);

// "  SETTING BEFORE ade / fde   AFTER ade / fde" per setting, the setting padded to `width`.
void PrintRepairedForecasts(const ForecastingFigures& f, int width, const char* before,
                            const char* after);

}  // namespace motionfork::app
