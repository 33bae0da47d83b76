// Choosing the imputation's last stage (fill_smoothing.h) on held-out training clips: how much to
// trust the calibrated fill against a smooth path in time, once for values bracketed by observed
// frames (on whole clips under every standard gap setting) and once for values observed on one side
// only (on histories of the model's window cut from the same clips, random shares missing, filled
// over the history alone as `predict --impute` does). Each lambda is the one of least summed
// relative error (squares / the spline's, per setting) over a fixed grid; 0 (no smoothing) is on
// the grid, so the stage is chosen only where it lowers that sum.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/progress.h"
#include "imputation/hgvae_model.h"
#include "imputation/refiner_fills.h"

namespace motionfork {

constexpr double kSmoothingLambdas[] = {0, 0.3, 1, 3, 10, 30, 100, 300, 1000};
constexpr double kSmoothingShares[] = {0.1, 0.5, 0.9};  // missing in the histories

struct SmoothingCalibration {
  FillSmoothing chosen;
  std::vector<std::pair<double, double>> bracketed;  // lambda, summed relative squares
  std::vector<std::pair<double, double>> one_sided;  // lambda (bracketed as chosen), the same
  int histories = 0;                                 // history windows per share
};

// A history of `window` frames cut from a held-out clip, a random share of its values missing
// (kSmoothingShares[share]): up to 8 spread over each clip, masks drawn from seed.
struct HeldOutHistory {
  size_t share = 0;
  std::vector<float> clean;   // [W, N]
  std::vector<uint8_t> mask;  // [W, N], 1 = missing
};
// used: how many windows each clip gave, summed (each gives one history per share).
std::vector<HeldOutHistory> HeldOutHistories(const std::vector<std::vector<float>>& clips,
                                             int window, int coords, uint64_t seed,
                                             int* used = nullptr);

// clips: root-relative poses without the root [T, N] on the model's skeleton; blend: the
// calibrated blend (its smoothing is ignored). Masks drawn from seed.
SmoothingCalibration CalibrateSmoothing(const HgvaeModel& model, const ImputationBlend& blend,
                                        const std::vector<std::vector<float>>& clips, uint64_t seed,
                                        const StageProgress& progress = nullptr);

}  // namespace motionfork
