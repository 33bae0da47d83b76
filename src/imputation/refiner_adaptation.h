// Adapting the imputation refiner's calibrated blend (ImputationBlend, refiner_fills.h) to one
// motion (no LibTorch). The calibration's weights per bucket are fitted on held-out training
// clips; a motion of another style (slower, noisier, another performer) may want more or less of
// the refiner's and the local polynomial's corrections, and of the bones' (a fill already closer
// than the bones' own spread of lengths is only moved off by them). The motion itself says how
// much: hide values it does observe in the same pattern as its missing ones (probes), fill them
// the same way, and fit each bucket's weights to those hidden values, pulled towards the
// calibrated ones (BestBlendWeights with a prior worth `adapt_values` values; chosen on held-out
// clips by `hgvae calibrate`). Observed values are never changed.
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
// is missing. Where that hides fewer than kProbeValues values (a few short gaps in a long motion),
// copies of the pattern shifted by s +- 5d, s +- 10d, ... are added, nearest first, until it
// hides that many: each run of missing frames only where it lands whole, d frames clear of every
// missing or already hidden value and of the motion's ends (so each copy looks like a gap of its
// own). [T, N] each, 1 = hidden; shifts that hide nothing are left out; empty when no coordinate
// is both observed and missing.
constexpr int64_t kProbeValues = 1024;
std::vector<std::vector<uint8_t>> RefinerProbes(const RefinerFills& f);

// One probe filled as f's missing values are: its fills (f's mask and the hidden values), the
// refiner's output for them and the hidden values ([T, N], 1 = hidden).
struct RefinerProbe {
  RefinerFills fills;
  std::vector<float> refined;
  std::vector<uint8_t> hidden;
};
// Every probe of f (RefinerProbes); skeleton: the motion's.
std::vector<RefinerProbe> FillRefinerProbes(const Skeleton& skeleton, const RefinerFills& f,
                                            const RawRefiner& refine);

// Per bucket, the sums (blend_fit.h) over the hidden values of the probes of f, with f's
// observed values as the truth.
BucketSums ProbeBlendSums(const std::vector<RefinerProbe>& probes, const RefinerFills& f);

// blend with each bucket's weights refitted to the probes' sums (BestBlendWeights with blend's
// weights as the prior, worth AdaptValues(blend, bucket) values); buckets the probes did not reach
// keep theirs.
ImputationBlend AdaptBlend(const ImputationBlend& blend, const BucketSums& probes);

// With blend.keep_bones: each bucket's share of the bones' correction (ImputationBlend::bones)
// fitted to the probes' hidden values as blend fills them, pulled towards all of it as if by
// AdaptValues(blend, bucket) values. Without keep_bones: blend as it is.
ImputationBlend AdaptBones(const Skeleton& skeleton, const ImputationBlend& blend,
                           const std::vector<RefinerProbe>& probes, const RefinerFills& f);

// Both adaptations with blend.adapt_values as the priors (blend as it is when none is > 0).
ImputationBlend AdaptToMotion(const Skeleton& skeleton, const RefinerFills& f,
                              const RawRefiner& refine, const ImputationBlend& blend);

}  // namespace motionfork
