// The forecasting figures of repaired histories (history_forecasting.h) as text for people, for the
// reports of the HG-VAE's and the Motion-DVAE's evaluation experiments.
#pragma once

#include <string>

#include "eval/history_forecasting.h"

namespace motionfork {

// A line per setting: "  SETTING BEFORE ade / fde   AFTER ade / fde", the setting padded to
// `width` (e.g. before "mean-imputed", after "HG-VAE-imputed").
std::string RepairedForecastsText(const ForecastingFigures& f, int width, const char* before,
                                  const char* after);

}  // namespace motionfork
