// Calibrating an HG-VAE bundle's imputation refiner on held-out training clips (ImputationBlend,
// refiner_fills.h): per bucket of missing values (the gap's length x its edges' speed x how
// crowded its frame is), how much of the refiner's correction of the spline and of the local
// polynomial's to add, and whether keeping the rigid bones at their lengths helps. Every standard
// gap setting (gap_imputation.h) is drawn on every clip; a bucket's two weights are the least-
// squares ones within [0, 1], each setting counted by its error relative to the spline's (so a
// 1-frame gap weighs as much as a 2 s one). How much to adapt those weights to each motion
// (refiner_adaptation.h) is chosen among kAdaptPriors by cross-fitting: weights fitted on half of
// the clips, adapted and scored on the other half. The bones are kept when that lowers the same
// sum. The figures per setting show the fit on the same clips (no test data is read).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/progress.h"
#include "imputation/hgvae_model.h"
#include "imputation/refiner_fills.h"
#include "imputation/training/smoothing_calibration.h"

namespace motionfork {

// The priors tried for the adaptation (values; 0: none).
constexpr double kAdaptPriors[] = {0, 3, 10, 30, 100, 300, 1000};

struct RefinerCalibration {
  ImputationBlend blend;               // refiner and local weights [kRefinerGapBuckets], bones
  std::vector<int64_t> bucket_values;  // missing values seen per bucket
  struct Setting {
    std::string name;
    int64_t values = 0;
    double spline_cm = 0, refiner_cm = 0, calibrated_cm = 0;  // RMS over the missing values
    double adapted_cm = 0;  // calibrated, then adapted to each clip as blend.adapt_values says
    double kept_cm = 0;     // adapted with the bone lengths kept (bone_lengths.h)
  };
  std::vector<Setting> settings;
  std::vector<std::pair<double, double>> adapt_scores;  // per prior: its cross-fitted sum
  // Each gap length class's prior (blend.adapt_values) chosen by its own share of those sums,
  // and the sum they make together.
  std::vector<double> length_priors;
  double length_score = 0;
  SmoothingCalibration smoothing;  // the last stage (blend.smoothing), chosen after the bones
  int clips = 0;
};

// clips: root-relative poses without the root [T, N] (HgvaeData's held-out clips), on the model's
// skeleton; masks drawn from seed. progress(done, total) after each clip. Throws
// std::invalid_argument when the model has no refiner or no clip takes any setting.
RefinerCalibration CalibrateRefiner(const HgvaeModel& model,
                                    const std::vector<std::vector<float>>& clips, uint64_t seed,
                                    const StageProgress& progress = nullptr);

// CalibrateRefiner on the bundle in model_dir, then the bundle with the weights written to out_dir
// (which must not be model_dir: the input is never overwritten).
RefinerCalibration CalibrateHgvaeBundle(const std::string& model_dir,
                                        const std::vector<std::vector<float>>& clips, uint64_t seed,
                                        const std::string& out_dir,
                                        const StageProgress& progress = nullptr);

// The table for people: per bucket its weight and values, per setting the three RMS figures, and
// the bundle written (`out`).
std::string RefinerCalibrationText(const RefinerCalibration& c, const std::string& out);

}  // namespace motionfork
