#include "eval/history_forecasting_text.h"

#include "core/text_format.h"

namespace motionfork {

std::string RepairedForecastsText(const ForecastingFigures& f, int width, const char* before,
                                  const char* after) {
  std::string s;
  for (const RepairedForecast& r : f.settings) {
    StringAppendf(&s, "  %-*s %s %.3f / %.3f   %s %.3f / %.3f\n", width, r.setting.c_str(), before,
                  r.before.ade, r.before.fde, after, r.after.ade, r.after.fde);
  }
  return s;
}

}  // namespace motionfork
