// Adapting the imputation refiner's calibrated blend (ImputationBlend, refiner_fills.h) to one
// motion (no LibTorch). The calibration's weights per bucket are fitted on held-out training
// clips; a motion of another style (slower, noisier, another performer) may want more or less of
// the refiner's and the local polynomial's corrections. The motion itself says how much: hide
// values it does observe in the same pattern as its missing ones (probes), fill them the same
// way, and fit each bucket's weights to those hidden values, pulled towards the calibrated ones
// (BestBlendWeights with a prior worth `adapt_values` values; chosen on held-out clips by
// `hgvae calibrate`). Observed values are never changed.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/skeleton.h"
#include "imputation/blend_fit.h"
#include "imputation/refiner_fills.h"

namespace motionfork {

// The refiner's output for fills, uncalibrated ([T, N] metres, HgvaeModel::Refine(f, false)).
using RawRefiner = std::function<std::vector<float>(const RefinerFills&)>;

// The probe masks of one motion's fills (f.frames rows): per time shift s in {+d, -d, +2d, -2d}
// (d: one more than the longest run of missing frames of a coordinate observed somewhere; shifts
// of at least the motion's length left out) the values observed in f whose value s frames earlier
// is missing. [T, N] each, 1 = hidden; shifts that hide nothing are left out; empty when no
// coordinate is both observed and missing.
std::vector<std::vector<uint8_t>> RefinerProbes(const RefinerFills& f);

// Per bucket, the sums (blend_fit.h) over the hidden values of every probe of f, filled as f's
// missing values are (the observed values of f as the truth); skeleton: the motion's.
BucketSums ProbeBlendSums(const Skeleton& skeleton, const RefinerFills& f,
                          const RawRefiner& refine);

// blend with each bucket's weights refitted to the probes (BestBlendWeights with blend's weights
// as the prior, worth prior_values values); buckets the probes did not reach keep theirs.
ImputationBlend AdaptBlend(const ImputationBlend& blend, const BucketSums& probes,
                           double prior_values);

}  // namespace motionfork
