#include "eval/history_forecasting_text.h"

#include <catch2/catch.hpp>
#include <string>

namespace motionfork {

TEST_CASE("repaired forecasts as text: a padded line per setting, before then after") {
  ForecastingFigures f;
  RepairedForecast r;
  r.setting = "gaussian:0.05";
  r.before.ade = 1.23456;
  r.before.fde = 2.0;
  r.after.ade = 0.5;
  r.after.fde = 0.75;
  f.settings = {r, r};
  f.settings[1].setting = "jitter";
  CHECK(RepairedForecastsText(f, 14, "noisy", "denoised") ==
        "  gaussian:0.05  noisy 1.235 / 2.000   denoised 0.500 / 0.750\n"
        "  jitter         noisy 1.235 / 2.000   denoised 0.500 / 0.750\n");
  CHECK(RepairedForecastsText(ForecastingFigures{}, 14, "a", "b").empty());
}

}  // namespace motionfork
