// Least-squares shares of the two corrections of a spline fill (no LibTorch): for the missing
// values of one bucket (refiner_fills.h), with e the spline's error (truth - spline), c the
// refiner's correction (refined - spline) and l the local polynomial's (local - spline), the
// (a, b) in [0, 1]^2 that minimise the sum of (e - a c - b l)^2. Used by the calibration on
// held-out clips (training/refiner_calibration.h) and by the adaptation to one motion
// (refiner_adaptation.h).
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "imputation/refiner_fills.h"

namespace motionfork {

struct BlendSums {
  enum Product { kEE, kCE, kCC, kLE, kLL, kCL, kProducts };
  std::array<double, kProducts> v{};
  int64_t values = 0;

  void Add(double e, double c, double l);
  BlendSums& operator+=(const BlendSums& o);
  BlendSums Scaled(double s) const;  // every product times s (values kept)
};
using BucketSums = std::vector<BlendSums>;  // [kRefinerGapBuckets]

// Squared error of spline + a c + b l over the sums.
double BlendSquares(const BlendSums& s, double a, double b);
// Over every bucket with weights a[k], b[k].
double BlendSquares(const BucketSums& s, const std::vector<double>& a,
                    const std::vector<double>& b);
// The (a, b) in [0, 1]^2 minimising BlendSquares(s, a, b); (0, 0) when nothing is known.
std::pair<double, double> BestBlendWeights(const BlendSums& s);
// The same pulled towards (a0, b0) as if by `prior_values` more values with the same corrections
// (the sums' own, scaled) whose errors a0 c + b0 l fits exactly. Sums without values or without
// any correction return (a0, b0).
std::pair<double, double> BestBlendWeights(const BlendSums& s, double a0, double b0,
                                           double prior_values);

// Adds every value of `which` (1 = counted; [T, N] like f.mask) to its bucket's sums, with truth
// and refined [T, N] as f.
void AddBlendSums(const RefinerFills& f, const std::vector<float>& refined,
                  const std::vector<float>& truth, const std::vector<uint8_t>& which,
                  BucketSums* sums);

}  // namespace motionfork
