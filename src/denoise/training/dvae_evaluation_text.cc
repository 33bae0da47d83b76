#include "denoise/training/dvae_evaluation_text.h"

#include <cmath>

#include "core/text_format.h"
#include "eval/history_forecasting_text.h"

namespace motionfork {
namespace {

// The value in `format`, or "-" where it was not measured (NaN).
std::string Number(double v, const char* format) {
  return std::isfinite(v) ? StringPrintf(format, v) : std::string("-");
}

}  // namespace

std::string DvaeEvaluationHeaderText(const DvaeEvaluation& e, const DvaeModel& model,
                                     const std::string& model_path) {
  std::string s = StringPrintf(
      "Motion-DVAE %s (%s parameters%s), %d test clips (%s frames, style '%s' unseen in "
      "training);\n"
      "clean acceleration %.2f m/s^2; %d posterior draws; optimisation mode on the first %d "
      "clips (%s frames), %d iterations;\n"
      "filters tuned for each noise on %d training clips (%s frames)\n",
      model_path.c_str(), WithThousands(model.num_parameters()).c_str(),
      model.manifest().finetuned ? ", fine-tuned on noisy data" : ", prior only", e.clips,
      WithThousands(e.frames).c_str(), e.test_style.c_str(), e.clean_accel, e.samples,
      e.optimisation_clips, WithThousands(e.optimisation_frames).c_str(), e.iterations,
      e.tuning_clips, WithThousands(e.tuning_frames).c_str());
  if (e.slow != 1) StringAppendf(&s, "test and tuning clips played %g times slower\n", e.slow);
  StringAppendf(&s,
                "\n%-18s %7s %8s %8s %8s %8s %8s %8s %8s %8s %9s %8s   accel / clean: noisy  "
                "best filter  denoised  refined  optimised\n",
                "noise (cm error)", "noisy", "gaussian", "sav-gol", "one-euro", "hampel",
                "denoised", "removed", "refined", "removed", "optimised", "removed");
  return s;
}

std::string DenoisingRowText(const DenoisingRow& r) {
  auto filter = [&r](size_t i) {
    return i < r.filters.size() ? StringPrintf("%.2f", r.filters[i].cm) : std::string("-");
  };
  const FilterFigure* best = r.best_filter();
  std::string s = StringPrintf(
      "%-18s %7.2f %8s %8s %8s %8s %8.2f %8s %8s %8s %9s %8s   %19.2f %12s %9.2f %8s %10s\n",
      r.noise.c_str(), r.noisy_cm, filter(0).c_str(), filter(1).c_str(), filter(2).c_str(),
      filter(3).c_str(), r.denoised_cm, Number(100 * r.removed, "%.1f%%").c_str(),
      Number(r.refined_cm, "%.2f").c_str(), Number(100 * r.removed_refined, "%.1f%%").c_str(),
      Number(r.optimised_cm, "%.2f").c_str(), Number(100 * r.removed_optimised, "%.1f%%").c_str(),
      r.accel_ratio_noisy, best ? StringPrintf("%.2f", best->accel_ratio).c_str() : "-",
      r.accel_ratio_denoised, Number(r.accel_ratio_refined, "%.2f").c_str(),
      Number(r.accel_ratio_optimised, "%.2f").c_str());
  for (const FilterFigure& f : r.filters) {
    StringAppendf(&s, "%-18s   %s: %s, %.2f cm on the tuning clips\n", "", f.filter.c_str(),
                  f.setting.c_str(), f.tuning_cm);
  }
  return s;
}

std::string DvaeEvaluationFooterText(const DvaeEvaluation& e, int threads) {
  std::string s = StringPrintf(
      "(filters: each with the parameters of least error on the tuning clips; optimised: on the "
      "first %d clips,\n"
      "against their own noisy error)\nspeed on %d thread(s): regression %.0f frames/s",
      e.optimisation_clips, threads, e.regression_frames_per_s);
  if (e.refiner) StringAppendf(&s, ", refiner %.0f frames/s", e.refiner_frames_per_s);
  if (e.optimisation_clips > 0) {
    StringAppendf(&s, ", optimisation %.0f frames/s (%d iterations per sequence)",
                  e.optimisation_frames_per_s, e.iterations);
  }
  s += "\n";
  if (e.forecasting) {
    const ForecastingFigures& f = *e.forecasting;
    StringAppendf(&s,
                  "\nforecasting (%s, K = %d, %d test windows, raw network output): ADE / FDE, "
                  "clean history %.3f / %.3f\n",
                  f.forecaster.c_str(), f.k, f.windows, f.clean.ade, f.clean.fde);
    s += RepairedForecastsText(f, 18, "noisy", "denoised");
  }
  return s;
}

}  // namespace motionfork
