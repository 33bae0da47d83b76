// The classical smoothing filters as tunable baselines (no LibTorch): one description of a filter
// and its parameters, a grid of candidate parameters per filter, and the grid search that picks
// the best on validation motions (never the test motions it is then reported on).
// Sequences are [frames, joints, 3] floats, metres.
#pragma once

#include <string>
#include <vector>

namespace motionfork {

enum class FilterKind {
  kGaussian,       // GaussianSmooth (denoise_metrics.h): a = sigma, frames
  kSavitzkyGolay,  // SavitzkyGolay (motion_filters.h): a = half window, frames; b = order
  kOneEuro,        // OneEuroFilter (motion_filters.h): a = min cutoff, Hz; b = beta, 1/m
  kHampel,         // HampelFilter (motion_filters.h): a = half window, frames; b = n_sigma
};

struct FilterSetting {
  FilterKind kind = FilterKind::kGaussian;
  double a = 0, b = 0;
};

// "gaussian", "savitzky-golay", "one-euro", "hampel".
std::string FilterName(FilterKind kind);
// The kind and its parameters, e.g. "savitzky-golay (half window 5, order 2)".
std::string DescribeFilter(const FilterSetting& setting);

// The filter applied to one sequence recorded at fps frames per second.
std::vector<float> ApplyFilter(const FilterSetting& setting, const std::vector<float>& p,
                               int joints, double fps);

// Candidate settings of a kind, from light to heavy smoothing: what a user tuning by hand would
// try (Gaussian sigma 0.5-8 frames; Savitzky-Golay half windows 2-15 frames of order 1-4; one-euro
// min cutoffs 0.1-8 Hz with beta 0-20; Hampel half windows 1-7 frames at 0-6 deviations).
std::vector<FilterSetting> FilterGrid(FilterKind kind);

struct TunedFilter {
  FilterSetting setting;
  double error_m = 0;  // mean joint error on the validation motions, metres
};

// The grid setting of `kind` with the lowest mean joint error (over every frame of every motion)
// between the filtered noisy[i] and clean[i]; ties go to the earlier (lighter) setting. `threads`
// candidates are tried at once; the result does not depend on it. Throws std::invalid_argument
// for no motions or noisy and clean of different sizes.
TunedFilter TuneFilter(FilterKind kind, const std::vector<std::vector<float>>& noisy,
                       const std::vector<std::vector<float>>& clean, int joints, double fps,
                       int threads = 1);

}  // namespace motionfork
