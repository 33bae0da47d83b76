// A generator bundle as the forecaster of the repaired-history experiments
// (eval/history_forecasting.h: the HG-VAE's and the Motion-DVAE's downstream figures).
#pragma once

#include <cstdint>
#include <string>

#include "eval/history_forecasting.h"

namespace motionfork {

// K futures per history, the network's raw output (the history is what differs, and the
// angle-range repair's cost grows with every implausible, e.g. mean-filled, history). dir "" =
// none (forecast left empty). History i of a call is forecast with ItemSeed(seed, i), histories
// shared by `threads` threads (pin LibTorch to one thread each with PinThreads(1)).
HistoryForecaster LoadHistoryForecaster(const std::string& dir, int k, uint64_t seed,
                                        int threads = 1);

}  // namespace motionfork
