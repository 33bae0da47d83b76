#include "eval/history_forecasting_json.h"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace motionfork {

nlohmann::ordered_json ForecastingJson(const ForecastingFigures& f, const std::string& setting_key,
                                       const std::string& before, const std::string& after) {
  nlohmann::ordered_json settings = nlohmann::ordered_json::array();
  for (const RepairedForecast& s : f.settings) {
    nlohmann::ordered_json row = {{setting_key, s.setting},
                                  {"ade_" + before, s.before.ade},
                                  {"fde_" + before, s.before.fde},
                                  {"ade_" + after, s.after.ade},
                                  {"fde_" + after, s.after.fde}};
    for (const auto& [name, d] : s.others) {
      std::string key = name;  // "rigid limb" -> "rigid_limb"
      std::replace(key.begin(), key.end(), ' ', '_');
      row["ade_" + key] = d.ade;
      row["fde_" + key] = d.fde;
    }
    settings.push_back(std::move(row));
  }
  return {{"forecaster", f.forecaster}, {"k", f.k},
          {"windows", f.windows},       {"repair", false},
          {"ade_clean", f.clean.ade},   {"fde_clean", f.clean.fde},
          {"settings", settings}};
}

}  // namespace motionfork
