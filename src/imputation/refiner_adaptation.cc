#include "imputation/refiner_adaptation.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

namespace motionfork {

namespace {

// A run of missing frames of one coordinate: frames [first, first + length).
struct MissingRun {
  int coord = 0, first = 0, length = 0;
};

std::vector<MissingRun> MissingRuns(const RefinerFills& f) {
  std::vector<MissingRun> runs;
  for (int v = 0; v < f.coords; ++v) {
    for (int t = 0; t < f.frames;) {
      if (!f.mask[static_cast<size_t>(t) * f.coords + v]) {
        ++t;
        continue;
      }
      int end = t;
      while (end < f.frames && f.mask[static_cast<size_t>(end) * f.coords + v]) ++end;
      runs.push_back({v, t, end - t});
      t = end;
    }
  }
  return runs;
}

}  // namespace

std::vector<std::vector<uint8_t>> RefinerProbes(const RefinerFills& f) {
  const int N = f.coords, T = f.frames;
  if (N <= 0 || T <= 0 || f.mask.size() != static_cast<size_t>(T) * N)
    throw std::invalid_argument("RefinerProbes: expected one window of fills");
  auto at = [N](int t, int v) { return static_cast<size_t>(t) * N + v; };
  std::vector<MissingRun> runs = MissingRuns(f);
  runs.erase(
      std::remove_if(runs.begin(), runs.end(), [T](const MissingRun& r) { return r.length >= T; }),
      runs.end());  // a coordinate never observed has nothing to hide
  int longest = 0;
  for (const MissingRun& r : runs) longest = std::max(longest, r.length);
  std::vector<std::vector<uint8_t>> probes;
  if (longest == 0) return probes;
  const int d = longest + 1, period = 5 * d;
  for (int shift : {d, -d, 2 * d, -2 * d}) {
    if (std::abs(shift) >= T) continue;
    std::vector<uint8_t> hide(f.mask.size(), 0);
    int64_t hidden = 0;
    for (const MissingRun& r : runs) {  // the pattern shifted, wherever it lands on observed values
      for (int t = std::max(0, r.first + shift); t < std::min(T, r.first + r.length + shift); ++t) {
        if (!f.mask[at(t, r.coord)] && !hide[at(t, r.coord)]) {
          hide[at(t, r.coord)] = 1;
          ++hidden;
        }
      }
    }
    // Sparse masks: more copies, `period` apart, nearest first, each run kept only where it lands
    // whole and d frames clear of every missing or already hidden value and of the motion's ends.
    std::vector<MissingRun> accepted;
    for (int m = 1; hidden < kProbeValues && m * period - std::abs(shift) < T; ++m) {
      for (const int copy : {shift + m * period, shift - m * period}) {
        accepted.clear();
        for (const MissingRun& r : runs) {
          const int first = r.first + copy, last = first + r.length - 1;
          if (first - d < 0 || last + d >= T) continue;
          bool clear = true;
          for (int t = first - d; t <= last + d && clear; ++t)
            clear = !f.mask[at(t, r.coord)] && !hide[at(t, r.coord)];
          if (clear) accepted.push_back({r.coord, first, r.length});
        }
        for (const MissingRun& r : accepted) {
          for (int t = r.first; t < r.first + r.length; ++t) {
            hidden += hide[at(t, r.coord)] == 0;
            hide[at(t, r.coord)] = 1;
          }
        }
      }
    }
    if (hidden > 0) probes.push_back(std::move(hide));
  }
  return probes;
}

std::vector<RefinerProbe> FillRefinerProbes(const Skeleton& skeleton, const RefinerFills& f,
                                            const RawRefiner& refine) {
  const int J = skeleton.num_joints(), N = f.coords, T = f.frames;
  if (N != 3 * (J - 1) || f.spline.size() != static_cast<size_t>(T) * N) {
    throw std::invalid_argument("FillRefinerProbes: expected fills of " +
                                std::to_string(3 * (J - 1)) + " coordinates (skeleton '" +
                                skeleton.name() + "'), got " + std::to_string(N));
  }
  // The motion as MakeRefinerFills takes it: the root at the origin, f's values (observed ones
  // as observed) at the other joints.
  const size_t F = static_cast<size_t>(J) * 3;
  std::vector<float> positions(static_cast<size_t>(T) * F, 0.0f);
  for (int t = 0; t < T; ++t) {
    std::copy(f.spline.begin() + static_cast<size_t>(t) * N,
              f.spline.begin() + static_cast<size_t>(t + 1) * N,
              positions.begin() + static_cast<size_t>(t) * F + 3);
  }
  std::vector<RefinerProbe> probes;
  for (std::vector<uint8_t>& hide : RefinerProbes(f)) {
    std::vector<uint8_t> missing(positions.size(), 0);
    for (int t = 0; t < T; ++t) {
      for (int v = 0; v < N; ++v) {
        const size_t i = static_cast<size_t>(t) * N + v;
        missing[static_cast<size_t>(t) * F + 3 + v] = f.mask[i] | hide[i];
      }
    }
    RefinerProbe p{MakeRefinerFills(skeleton, positions, missing, f.fallback), {}, std::move(hide)};
    p.refined = refine(p.fills);
    probes.push_back(std::move(p));
  }
  return probes;
}

BucketSums ProbeBlendSums(const std::vector<RefinerProbe>& probes, const RefinerFills& f) {
  BucketSums sums(kRefinerGapBuckets);
  for (const RefinerProbe& p : probes) AddBlendSums(p.fills, p.refined, f.spline, p.hidden, &sums);
  return sums;
}

ImputationBlend AdaptBlend(const ImputationBlend& blend, const BucketSums& probes) {
  if (probes.size() != static_cast<size_t>(kRefinerGapBuckets)) {
    throw std::invalid_argument("AdaptBlend: expected sums for " +
                                std::to_string(kRefinerGapBuckets) + " buckets, got " +
                                std::to_string(probes.size()));
  }
  ImputationBlend out = blend;
  out.refiner.assign(kRefinerGapBuckets, 1.0);
  out.local.assign(kRefinerGapBuckets, 0.0);
  for (int k = 0; k < kRefinerGapBuckets; ++k) {
    const double a0 = blend.refiner.empty() ? 1.0 : blend.refiner[k];
    const double b0 = blend.local.empty() ? 0.0 : blend.local[k];
    std::tie(out.refiner[k], out.local[k]) =
        BestBlendWeights(probes[k], a0, b0, AdaptValues(blend, k));
  }
  return out;
}

ImputationBlend AdaptBones(const Skeleton& skeleton, const ImputationBlend& blend,
                           const std::vector<RefinerProbe>& probes, const RefinerFills& f) {
  if (!blend.keep_bones) return blend;
  ImputationBlend loose = blend, rigid = blend;
  loose.keep_bones = false;
  rigid.bones.clear();
  // The Gaussian's estimates depend on the observed values only: they would make both fills of a
  // hidden value it fills the same, hiding what the bones do there.
  loose.gaussian = rigid.gaussian = nullptr;
  // Per bucket: e the blend's error on the hidden values, c the bones' correction of it.
  BucketSums sums(kRefinerGapBuckets);
  for (const RefinerProbe& p : probes) {
    const std::vector<float> loose_fill = BlendRefinerFills(skeleton, p.fills, p.refined, loose);
    const std::vector<float> kept = BlendRefinerFills(skeleton, p.fills, p.refined, rigid);
    const std::vector<int> buckets = RefinerGapBuckets(p.fills);
    for (size_t i = 0; i < loose_fill.size(); ++i) {
      if (p.hidden[i] && buckets[i] >= 0)
        sums[buckets[i]].Add(double(f.spline[i]) - loose_fill[i], double(kept[i]) - loose_fill[i],
                             0.0);
    }
  }
  ImputationBlend out = blend;
  out.bones.assign(kRefinerGapBuckets, 1.0);
  for (int k = 0; k < kRefinerGapBuckets; ++k) {
    const double prior = blend.bones.empty() ? 1.0 : blend.bones[k];
    out.bones[k] = BestBlendWeights(sums[k], prior, 0.0, AdaptValues(blend, k)).first;
  }
  return out;
}

ImputationBlend AdaptToMotion(const Skeleton& skeleton, const RefinerFills& f,
                              const RawRefiner& refine, const ImputationBlend& blend) {
  if (!AdaptsToMotion(blend)) return blend;
  const std::vector<RefinerProbe> probes = FillRefinerProbes(skeleton, f, refine);
  if (probes.empty()) return blend;
  return AdaptBones(skeleton, AdaptBlend(blend, ProbeBlendSums(probes, f)), probes, f);
}

}  // namespace motionfork
