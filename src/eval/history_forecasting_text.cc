#include "eval/history_forecasting_text.h"

#include "core/text_format.h"

namespace motionfork {

std::string RepairedForecastsText(const ForecastingFigures& f, int width, const char* before,
                                  const char* after) {
  std::string s;
  for (const RepairedForecast& r : f.settings) {
    StringAppendf(&s, "  %-*s %s %.3f / %.3f   %s %.3f / %.3f", width, r.setting.c_str(), before,
                  r.before.ade, r.before.fde, after, r.after.ade, r.after.fde);
    for (const auto& [name, d] : r.others)
      StringAppendf(&s, "   %s %.3f / %.3f", name.c_str(), d.ade, d.fde);
    s += "\n";
  }
  return s;
}

}  // namespace motionfork
