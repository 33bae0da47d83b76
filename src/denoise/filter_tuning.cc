#include "denoise/filter_tuning.h"

#include <cmath>
#include <stdexcept>

#include "core/parallel_for.h"
#include "core/text_format.h"
#include "denoise/denoise_metrics.h"
#include "denoise/motion_filters.h"

namespace motionfork {

std::string FilterName(FilterKind kind) {
  switch (kind) {
    case FilterKind::kGaussian:
      return "gaussian";
    case FilterKind::kSavitzkyGolay:
      return "savitzky-golay";
    case FilterKind::kOneEuro:
      return "one-euro";
    case FilterKind::kHampel:
      return "hampel";
  }
  return "?";
}

std::string DescribeFilter(const FilterSetting& s) {
  switch (s.kind) {
    case FilterKind::kGaussian:
      return StringPrintf("gaussian (sigma %.3g frames)", s.a);
    case FilterKind::kSavitzkyGolay:
      return StringPrintf("savitzky-golay (half window %.0f, order %.0f)", s.a, s.b);
    case FilterKind::kOneEuro:
      return StringPrintf("one-euro (min cutoff %.3g Hz, beta %.3g)", s.a, s.b);
    case FilterKind::kHampel:
      return StringPrintf("hampel (half window %.0f, %.3g deviations)", s.a, s.b);
  }
  return "?";
}

std::vector<float> ApplyFilter(const FilterSetting& s, const std::vector<float>& p, int joints,
                               double fps) {
  switch (s.kind) {
    case FilterKind::kGaussian:
      return GaussianSmooth(p, joints, s.a);
    case FilterKind::kSavitzkyGolay:
      return SavitzkyGolay(p, joints, static_cast<int>(s.a), static_cast<int>(s.b));
    case FilterKind::kOneEuro:
      return OneEuroFilter(p, joints, fps, s.a, s.b);
    case FilterKind::kHampel:
      return HampelFilter(p, joints, static_cast<int>(s.a), s.b);
  }
  throw std::invalid_argument("ApplyFilter: unknown filter kind");
}

std::vector<FilterSetting> FilterGrid(FilterKind kind) {
  std::vector<FilterSetting> grid;
  switch (kind) {
    case FilterKind::kGaussian:
      for (double sigma : {0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0})
        grid.push_back({kind, sigma, 0});
      break;
    case FilterKind::kSavitzkyGolay:
      for (int half : {2, 3, 4, 5, 6, 8, 10, 12, 15}) {
        for (int order = 1; order <= 4; ++order) {
          if (order < 2 * half) grid.push_back({kind, double(half), double(order)});
        }
      }
      break;
    case FilterKind::kOneEuro:
      for (double cutoff : {0.1, 0.2, 0.5, 1.0, 2.0, 4.0, 8.0}) {
        for (double beta : {0.0, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0})
          grid.push_back({kind, cutoff, beta});
      }
      break;
    case FilterKind::kHampel:
      for (int half : {1, 2, 3, 4, 5, 7}) {
        for (double n_sigma : {0.0, 1.0, 2.0, 3.0, 4.0, 6.0})
          grid.push_back({kind, double(half), n_sigma});
      }
      break;
  }
  return grid;
}

TunedFilter TuneFilter(FilterKind kind, const std::vector<std::vector<float>>& noisy,
                       const std::vector<std::vector<float>>& clean, int joints, double fps,
                       int threads) {
  if (noisy.empty() || noisy.size() != clean.size()) {
    throw std::invalid_argument(
        "TuneFilter: expected as many clean as noisy motions (at least one)"
        ", got " +
        std::to_string(clean.size()) + " and " + std::to_string(noisy.size()));
  }
  double frames = 0;
  for (size_t i = 0; i < noisy.size(); ++i) {
    if (noisy[i].size() != clean[i].size()) {
      throw std::invalid_argument("TuneFilter: motion " + std::to_string(i) + " has " +
                                  std::to_string(noisy[i].size()) + " noisy values and " +
                                  std::to_string(clean[i].size()) + " clean ones");
    }
    frames += static_cast<double>(noisy[i].size() / (3 * joints));
  }
  const std::vector<FilterSetting> grid = FilterGrid(kind);
  std::vector<double> error(grid.size());
  ParallelFor(static_cast<int>(grid.size()), threads, [&](int g, int) {
    double sum = 0;
    for (size_t i = 0; i < noisy.size(); ++i) {
      const double n = static_cast<double>(noisy[i].size() / (3 * joints));
      sum += MeanJointError(ApplyFilter(grid[g], noisy[i], joints, fps), clean[i]) * n;
    }
    error[g] = sum / frames;
  });
  size_t best = 0;
  for (size_t g = 1; g < grid.size(); ++g) {
    if (error[g] < error[best]) best = g;
  }
  return {grid[best], error[best]};
}

}  // namespace motionfork
