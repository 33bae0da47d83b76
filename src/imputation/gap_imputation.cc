#include "imputation/gap_imputation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <stdexcept>

#include "core/parallel_for.h"
#include "imputation/interpolation_fill.h"
#include "imputation/motion_imputation.h"

namespace motionfork {
namespace {

// The first of the names the skeleton has.
std::optional<int> FindAny(const Skeleton& skeleton, std::initializer_list<const char*> names) {
  for (const char* n : names) {
    if (const auto j = skeleton.Find(n)) return j;
  }
  return std::nullopt;
}

std::string GapName(const std::string& group, int frames, double fps) {
  if (frames == 0) return group + ", whole clip";
  if (frames == 1) return group + ", 1 frame gap";
  char seconds[32];
  std::snprintf(seconds, sizeof(seconds), "%.3g", frames / fps);
  return group + ", " + seconds + " s gap";
}

}  // namespace

std::vector<GapSetting> StandardGapSettings(const Skeleton& skeleton, double fps) {
  std::vector<GapSetting> out;
  for (double s : {0.01, 0.10, 0.50, 0.90}) {
    out.push_back({"random " + std::to_string(static_cast<int>(s * 100 + 0.5)) + "%", s, {}, 0});
  }
  std::vector<std::pair<std::string, std::vector<int>>> groups;
  if (const auto hand = FindAny(skeleton, {"Hand_L", "LeftHand", "LWrist", "LeftWrist"}))
    groups.push_back({"left hand", {*hand}});
  if (const auto arm = FindAny(skeleton, {"UpperArm_L", "LeftArm", "LShoulder"}))
    groups.push_back({"left arm", skeleton.Subtree(*arm)});
  if (!skeleton.partitions().empty() && skeleton.partitions()[0].parts.size() > 1) {
    for (const BodyPart& part : skeleton.partitions()[0].parts)
      groups.push_back({part.name, part.joints});
  }
  const int lengths[] = {
      1, static_cast<int>(std::lround(0.25 * fps)), static_cast<int>(std::lround(0.5 * fps)),
      static_cast<int>(std::lround(fps)), static_cast<int>(std::lround(2 * fps))};
  for (const auto& [group, joints] : groups) {
    std::vector<int> js;
    for (int j : joints) {
      if (j != 0) js.push_back(j);
    }
    if (js.empty()) continue;
    int previous = 0;
    for (int frames : lengths) {
      frames = std::max(frames, 1);
      if (frames == previous) continue;  // a low frame rate: 0.25 s may be one frame
      previous = frames;
      out.push_back({GapName(group, frames, fps), 0, js, frames});
    }
    out.push_back({GapName(group, 0, fps), 0, js, 0});
  }
  return out;
}

std::vector<uint8_t> GapMask(const GapSetting& setting, int frames, int joints, uint64_t seed) {
  const size_t F = static_cast<size_t>(joints) * 3;
  std::vector<uint8_t> mask(static_cast<size_t>(frames) * F, 0);
  std::mt19937_64 rng(seed);
  if (setting.share > 0) {
    std::vector<size_t> values;
    for (int t = 0; t < frames; ++t) {
      for (size_t v = 3; v < F; ++v) values.push_back(t * F + v);
    }
    const size_t count =
        std::min(values.size(), static_cast<size_t>(std::llround(setting.share * values.size())));
    for (size_t i = 0; i < count; ++i) {  // a partial Fisher-Yates shuffle
      const size_t k = i + std::uniform_int_distribution<size_t>(0, values.size() - 1 - i)(rng);
      std::swap(values[i], values[k]);
      mask[values[i]] = 1;
    }
    return mask;
  }
  int first = 0, last = frames - 1;
  if (setting.gap_frames > 0) {
    if (frames < setting.gap_frames + 2) return {};
    first = std::uniform_int_distribution<int>(1, frames - 1 - setting.gap_frames)(rng);
    last = first + setting.gap_frames - 1;
  }
  for (int t = first; t <= last; ++t) {
    for (int j : setting.joints) {
      for (int a = 0; a < 3; ++a) mask[t * F + j * 3 + a] = 1;
    }
  }
  return mask;
}

const std::vector<FillMethod>& AllFillMethods() {
  static const std::vector<FillMethod> all = {
      FillMethod::kMean,      FillMethod::kLinear, FillMethod::kCubicSpline,
      FillMethod::kRigidLimb, FillMethod::kHgvae,  FillMethod::kHgvaeFromSpline,
      FillMethod::kRefiner};
  return all;
}

std::string FillMethodName(FillMethod method) {
  switch (method) {
    case FillMethod::kMean:
      return "mean";
    case FillMethod::kLinear:
      return "linear";
    case FillMethod::kCubicSpline:
      return "spline";
    case FillMethod::kRigidLimb:
      return "rigid limb";
    case FillMethod::kHgvae:
      return "hg-vae";
    case FillMethod::kHgvaeFromSpline:
      return "hg-vae+spline";
    case FillMethod::kRefiner:
      return "refiner";
  }
  return "?";
}

std::vector<float> FillMotion(FillMethod method, const HgvaeModel& model, const Motion& motion,
                              const std::vector<uint8_t>& missing, const ImputeOptions& options) {
  const int J = motion.num_joints(), T = motion.num_frames();
  const std::vector<float>& p = motion.positions();
  switch (method) {
    case FillMethod::kMean: {
      const std::vector<float> mean = TrainingMeanPose(model);
      std::vector<float> out = p;
      for (int t = 0; t < T; ++t) {
        for (int v = 3; v < 3 * J; ++v) {
          const size_t i = static_cast<size_t>(t) * J * 3 + v;
          if (missing[i]) out[i] = p[static_cast<size_t>(t) * J * 3 + v % 3] + mean[v];
        }
      }
      return out;
    }
    case FillMethod::kLinear:
      return InterpolateMissing(p, missing, J, Interpolation::kLinear, TrainingMeanPose(model));
    case FillMethod::kCubicSpline:
      return InterpolateMissing(p, missing, J, Interpolation::kCubicSpline,
                                TrainingMeanPose(model));
    case FillMethod::kRigidLimb:
      return RigidLimbFill(motion.skeleton(), p, missing, TrainingMeanPose(model));
    case FillMethod::kHgvae:
    case FillMethod::kHgvaeFromSpline:
    case FillMethod::kRefiner: {
      ImputeOptions o = options;  // the HG-VAE's steps from the mean or the spline; the refiner
      o.start = method == FillMethod::kHgvae             ? ImputeStart::kMean
                : method == FillMethod::kHgvaeFromSpline ? ImputeStart::kSpline
                                                         : ImputeStart::kRefiner;
      if (method == FillMethod::kRefiner)
        o.steps = 0;  // alone
      else if (o.steps == 0)
        o.steps = ImputeOptions{}.steps;
      return ImputeMotion(model, motion, missing, o).motion.positions();
    }
  }
  throw std::invalid_argument("FillMotion: unknown method");
}

double GapFigure::best_baseline_cm() const {
  const int b = best_baseline();
  return b < 0 ? NAN : rms_cm[b];
}

int GapFigure::best_baseline() const {
  int best = -1;
  for (size_t m = 0; m < rms_cm.size() && m < AllFillMethods().size(); ++m) {
    const FillMethod method = AllFillMethods()[m];
    if (method == FillMethod::kHgvae || method == FillMethod::kHgvaeFromSpline ||
        method == FillMethod::kRefiner)
      continue;
    if (best < 0 || rms_cm[m] < rms_cm[best]) best = static_cast<int>(m);
  }
  return best;
}

std::vector<GapFigure> GapExperiment(const HgvaeModel& model, const std::vector<Motion>& motions,
                                     const std::vector<GapSetting>& settings,
                                     const ImputeOptions& options, uint64_t seed,
                                     const std::function<void(int, int)>& progress) {
  const std::vector<FillMethod>& methods = AllFillMethods();
  std::vector<GapFigure> out;
  for (size_t s = 0; s < settings.size(); ++s) {
    GapFigure f{settings[s], 0, 0, std::vector<double>(methods.size(), 0.0)};
    std::vector<double> squares(methods.size(), 0.0);
    for (size_t c = 0; c < motions.size(); ++c) {
      const Motion& motion = motions[c];
      const std::vector<uint8_t> mask =
          GapMask(settings[s], motion.num_frames(), motion.num_joints(),
                  ItemSeed(seed, static_cast<int>(s * 100003 + c)));
      const int64_t count = std::count(mask.begin(), mask.end(), 1);
      if (count == 0) continue;
      ++f.motions;
      f.missing_values += count;
      for (size_t m = 0; m < methods.size(); ++m) {
        if (methods[m] == FillMethod::kRefiner && !model.has_refiner()) {
          squares[m] = NAN;
          continue;
        }
        const std::vector<float> filled = FillMotion(methods[m], model, motion, mask, options);
        for (size_t i = 0; i < mask.size(); ++i) {
          if (!mask[i]) continue;
          const double d = filled[i] - motion.positions()[i];
          squares[m] += d * d;
        }
      }
    }
    for (size_t m = 0; m < methods.size(); ++m) {
      f.rms_cm[m] = f.missing_values > 0 ? 100 * std::sqrt(squares[m] / f.missing_values) : NAN;
    }
    out.push_back(std::move(f));
    if (progress) progress(static_cast<int>(s + 1), static_cast<int>(settings.size()));
  }
  return out;
}

}  // namespace motionfork
