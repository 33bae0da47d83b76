#include "denoise/training/dvae_evaluation_text.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

namespace motionfork {

TEST_CASE("evaluation text: a row shows '-' where optimisation or refiner mode did not run") {
  DenoisingRow r;
  r.noise = "gaussian:0.02";
  r.noisy_cm = 3.5;
  r.filters = {{"gaussian", "gaussian (sigma 2 frames)", 2.0, 2.25, 0.357, 2},
               {"savitzky-golay", "savitzky-golay (half window 5, order 2)", 2.1, 2.5, 0.28, 3},
               {"one-euro", "one-euro (min cutoff 1 Hz, beta 0.5)", 2.6, 2.75, 0.2, 4},
               {"hampel", "hampel (half window 3, 3 deviations)", 2.8, 3.0, 0.14, 1.5}};
  r.denoised_cm = 1.5;
  r.removed = 0.5714;
  r.optimised_cm = std::nan("");
  r.removed_optimised = std::nan("");
  r.accel_ratio_noisy = 10;
  r.accel_ratio_denoised = 1.25;
  r.accel_ratio_optimised = std::nan("");
  const std::string row = DenoisingRowText(r);
  CHECK(row.rfind("gaussian:0.02", 0) == 0);
  CHECK(row.find("3.50") != std::string::npos);
  CHECK(row.find("57.1%") != std::string::npos);
  CHECK(row.find(" - ") != std::string::npos);
  CHECK(row.back() == '\n');
  CHECK(row.find("nan") == std::string::npos);
  // Every filter's test error in the row, the best one's acceleration, each setting below.
  CHECK(row.find(" 2.25 ") != std::string::npos);
  CHECK(row.find(" 2.50 ") != std::string::npos);
  CHECK(row.find(" 2.75 ") != std::string::npos);
  CHECK(row.find(" 3.00 ") != std::string::npos);
  CHECK(row.find("savitzky-golay (half window 5, order 2), 2.10 cm on the tuning clips\n") !=
        std::string::npos);
  CHECK(r.best_filter() == &r.filters[0]);
  r.optimised_cm = 1.0;
  r.removed_optimised = 0.7143;
  r.accel_ratio_optimised = 1.1;
  CHECK(DenoisingRowText(r).find("71.4%") != std::string::npos);
  CHECK(DenoisingRowText(r).find(" - ") != std::string::npos);  // no refiner
  r.refined_cm = 1.25;
  r.removed_refined = 0.6429;
  r.accel_ratio_refined = 0.95;
  const std::string full = DenoisingRowText(r);
  CHECK(full.find(" 1.25 ") != std::string::npos);
  CHECK(full.find("64.3%") != std::string::npos);
  CHECK(full.find(" - ") == std::string::npos);
}

TEST_CASE("evaluation text: the footer gives the speed and, when measured, forecasting") {
  DvaeEvaluation e;
  e.regression_frames_per_s = 12345.6;
  std::string s = DvaeEvaluationFooterText(e, 2);
  CHECK(s.find("speed on 2 thread(s): regression 12346 frames/s\n") != std::string::npos);
  CHECK(s.find("optimised: on the first 0 clips") != std::string::npos);
  CHECK(s.find("forecasting") == std::string::npos);
  e.optimisation_clips = 3;
  e.optimisation_frames_per_s = 50;
  e.iterations = 7;
  e.forecasting = ForecastingFigures{};
  e.forecasting->forecaster = "zero-velocity";
  s = DvaeEvaluationFooterText(e, 1);
  CHECK(s.find(", optimisation 50 frames/s (7 iterations per sequence)") != std::string::npos);
  CHECK(s.find("forecasting (zero-velocity") != std::string::npos);
}

}  // namespace motionfork
