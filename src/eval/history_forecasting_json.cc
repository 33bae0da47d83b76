#include "eval/history_forecasting_json.h"

#include <nlohmann/json.hpp>

namespace motionfork {

nlohmann::ordered_json ForecastingJson(const ForecastingFigures& f, const std::string& setting_key,
                                       const std::string& before, const std::string& after) {
  nlohmann::ordered_json settings = nlohmann::ordered_json::array();
  for (const RepairedForecast& s : f.settings) {
    settings.push_back({{setting_key, s.setting},
                        {"ade_" + before, s.before.ade},
                        {"fde_" + before, s.before.fde},
                        {"ade_" + after, s.after.ade},
                        {"fde_" + after, s.after.fde}});
  }
  return {{"forecaster", f.forecaster}, {"k", f.k},
          {"windows", f.windows},       {"repair", false},
          {"ade_clean", f.clean.ade},   {"fde_clean", f.clean.fde},
          {"settings", settings}};
}

}  // namespace motionfork
