#include "imputation/training/smoothing_calibration.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>

#include "core/parallel_for.h"
#include "imputation/gap_imputation.h"
#include "imputation/motion_imputation.h"
#include "imputation/occlusion.h"
#include "imputation/refiner_adaptation.h"

namespace motionfork {
namespace {

// One filled motion: its clean values, the fills, the calibrated fill before smoothing, and the
// setting it counts towards.
struct Filled {
  size_t setting = 0;
  std::vector<float> clean;
  RefinerFills fills;
  std::vector<float> blended;
};

// Per lambda on the grid, the sum over settings of smoothed squares / spline squares, with
// smoothing_of(lambda) as the stage.
std::vector<std::pair<double, double>> Scores(
    const std::vector<Filled>& items, size_t settings,
    const std::function<FillSmoothing(double)>& smoothing_of) {
  std::vector<double> spline(settings, 0.0);
  for (const Filled& it : items)
    for (size_t i = 0; i < it.clean.size(); ++i)
      if (it.fills.mask[i])
        spline[it.setting] += std::pow(double(it.fills.spline[i]) - it.clean[i], 2);
  std::vector<std::pair<double, double>> out;
  for (const double lambda : kSmoothingLambdas) {
    std::vector<double> squares(settings, 0.0);
    for (const Filled& it : items) {
      const std::vector<float> s =
          SmoothFilledValues(it.blended, it.fills.mask, it.fills.coords, smoothing_of(lambda));
      for (size_t i = 0; i < s.size(); ++i)
        if (it.fills.mask[i]) squares[it.setting] += std::pow(double(s[i]) - it.clean[i], 2);
    }
    double total = 0;
    for (size_t k = 0; k < settings; ++k)
      if (spline[k] > 0) total += squares[k] / spline[k];
    out.push_back({lambda, total});
  }
  return out;
}

double Lowest(const std::vector<std::pair<double, double>>& scores) {
  return std::min_element(scores.begin(), scores.end(),
                          [](const auto& a, const auto& b) { return a.second < b.second; })
      ->first;
}

}  // namespace

std::vector<HeldOutHistory> HeldOutHistories(const std::vector<std::vector<float>>& clips,
                                             int window, int coords, uint64_t seed, int* used) {
  const size_t W = static_cast<size_t>(window), N = static_cast<size_t>(coords);
  constexpr int kWindowsPerClip = 8;
  std::vector<HeldOutHistory> out;
  if (used) *used = 0;
  for (size_t c = 0; c < clips.size(); ++c) {
    const int count = static_cast<int>(clips[c].size() / N / W);
    const int taken = std::min(count, kWindowsPerClip);
    for (int w = 0; w < taken; ++w) {
      const size_t start = static_cast<size_t>(w * count / taken) * W * N;
      for (size_t s = 0; s < std::size(kSmoothingShares); ++s) {
        HeldOutHistory h;
        h.share = s;
        h.clean.assign(clips[c].begin() + start, clips[c].begin() + start + W * N);
        h.mask = RandomOcclusion(1, static_cast<int>(W * N), kSmoothingShares[s],
                                 ItemSeed(seed + 7, static_cast<int>(c * 1009 + w * 7 + s)));
        out.push_back(std::move(h));
      }
    }
    if (used) *used += taken;
  }
  return out;
}

SmoothingCalibration CalibrateSmoothing(const HgvaeModel& model, const ImputationBlend& blend,
                                        const std::vector<std::vector<float>>& clips, uint64_t seed,
                                        const StageProgress& progress) {
  const Skeleton& skeleton = model.skeleton();
  const int J = skeleton.num_joints(), N = 3 * (J - 1), W = model.window();
  const std::vector<float> fallback = TrainingMeanPose(model);
  const RawRefiner raw = [&model](const RefinerFills& f) { return model.Refine(f, false); };
  ImputationBlend plain = blend;
  plain.smoothing = {};
  plain.gaussian = nullptr;
  // clean: [T, N]; missing: [T, J, 3] (the root observed).
  auto fill = [&](size_t setting, std::vector<float> clean, const std::vector<uint8_t>& missing) {
    const size_t T = clean.size() / N;
    Filled it{setting, std::move(clean), {}, {}};
    it.fills =
        MakeRefinerFills(skeleton, WithRootAtOrigin(it.clean.data(), T, N), missing, fallback);
    const std::vector<float> refined = raw(it.fills);
    it.blended = BlendRefinerFills(skeleton, it.fills, refined,
                                   AdaptToMotion(skeleton, it.fills, raw, plain));
    return it;
  };
  // Whole clips under every gap setting (masks as CalibrateRefiner draws them).
  const std::vector<GapSetting> settings = StandardGapSettings(skeleton, model.manifest().fps);
  std::vector<Filled> whole, histories;
  size_t done = 0;
  const size_t total = clips.size() + 1;
  for (size_t c = 0; c < clips.size(); ++c) {
    const int T = static_cast<int>(clips[c].size() / N);
    for (size_t s = 0; s < settings.size(); ++s) {
      const std::vector<uint8_t> mask =
          GapMask(settings[s], T, J, ItemSeed(seed, static_cast<int>(s * 100003 + c)));
      if (std::count(mask.begin(), mask.end(), 1) == 0) continue;
      whole.push_back(fill(s, clips[c], mask));
    }
    ReportProgress(progress, "smoothing on held-out clips", double(++done) / total);
  }
  SmoothingCalibration out;
  for (HeldOutHistory& h : HeldOutHistories(clips, W, N, seed, &out.histories))
    histories.push_back(fill(h.share, std::move(h.clean), WithRootAtOrigin(h.mask.data(), W, N)));
  ReportProgress(progress, "smoothing on held-out clips", 1.0);
  out.bracketed = Scores(whole, settings.size(), [](double l) { return FillSmoothing{l, 0}; });
  out.chosen.bracketed = Lowest(out.bracketed);
  const double b = out.chosen.bracketed;
  out.one_sided = Scores(histories, std::size(kSmoothingShares), [b](double l) {
    return FillSmoothing{b, l};
  });
  out.chosen.one_sided = Lowest(out.one_sided);
  return out;
}

}  // namespace motionfork
