// Calibrating an HG-VAE bundle's imputation refiner on held-out training clips: how much of its
// correction of the spline to keep in each bucket of missing values (refiner_fills.h: the gap's
// length x how crowded its frame is). Every standard gap setting (gap_imputation.h) is drawn on
// every clip; a bucket's weight is the least-squares one, each setting counted by its error
// relative to the spline's (so a 1-frame gap weighs as much as a 2 s one), clamped to [0, 1]: 0
// keeps the spline, 1 the refiner as trained. The figures per setting show the fit on the same
// clips (no test data is read).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/progress.h"
#include "imputation/hgvae_model.h"

namespace motionfork {

struct RefinerCalibration {
  std::vector<double> weights;         // [kRefinerGapBuckets]
  std::vector<int64_t> bucket_values;  // missing values seen per bucket
  struct Setting {
    std::string name;
    int64_t values = 0;
    double spline_cm = 0, refiner_cm = 0, calibrated_cm = 0;  // RMS over the missing values
  };
  std::vector<Setting> settings;
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
