// Imputation over whole motions, the HG-VAE beside the classical fills a user would otherwise
// pick (no LibTorch): values missing at random over a clip, gaps from one frame to two seconds of
// a joint, a limb or a body part, and a part missing for the whole clip. Every method fills the
// same masks; the figure is the RMS error of the filled values.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/motion.h"
#include "imputation/hgvae_model.h"

namespace motionfork {

struct GapSetting {
  std::string name;         // "random 10%", "left arm, 0.5 s gap", "legs, whole clip"
  double share = 0;         // > 0: this share of the non-root values, at random over the clip
  std::vector<int> joints;  // otherwise: these joints (never the root) ...
  int gap_frames = 0;       // ... over a gap of this many frames (0: every frame of the clip)
};

// The settings for a skeleton recorded at fps: random 1%, 10%, 50%, 90%; gaps of 1 frame,
// 0.25, 0.5, 1 and 2 s of one joint (the left hand), of a limb (the left arm) and of each part of
// the skeleton's default partition (legs, upper body); each of those groups missing for the
// whole clip. Joints found by the skeleton's names (Bandai, Human3.6M and VideoPose3D spellings);
// groups it does not have are left out.
std::vector<GapSetting> StandardGapSettings(const Skeleton& skeleton, double fps);

// The mask [frames, joints, 3] (1 = missing) of one setting on a motion, reproducible for a seed:
// random values exactly round(share x the non-root values); a gap at a random start that leaves
// at least one observed frame on each side (bracketed). Empty when the motion is too short to
// bracket the gap.
std::vector<uint8_t> GapMask(const GapSetting& setting, int frames, int joints, uint64_t seed);

// The fills compared, in table order.
enum class FillMethod {
  kMean,
  kLinear,
  kCubicSpline,
  kRigidLimb,
  kHgvae,
  kHgvaeFromSpline,
  kRefiner
};
const std::vector<FillMethod>& AllFillMethods();
// "mean", "linear", "spline", "rigid limb", "hg-vae", "hg-vae+spline", "refiner"
std::string FillMethodName(FillMethod method);

// One method's fill of motion's missing values (observed ones unchanged). Mean: the HG-VAE's
// training mean pose about the frame's root; linear / spline: InterpolateMissing, rigid limb:
// RigidLimbFill (interpolation_fill.h), both falling back on the mean pose where a value is never
// observed; hg-vae: ImputeMotion (motion_imputation.h) with `options`, hg-vae+spline: the same
// starting from the spline (ImputeStart::kSpline), both with options' steps (the default 10 where
// they are 0); refiner: the bundle's refiner alone (ImputeStart::kRefiner, no steps).
std::vector<float> FillMotion(FillMethod method, const HgvaeModel& model, const Motion& motion,
                              const std::vector<uint8_t>& missing, const ImputeOptions& options);

struct GapFigure {
  GapSetting setting;
  int motions = 0;  // clips the setting could be applied to
  int64_t missing_values = 0;
  std::vector<double> rms_cm;  // per AllFillMethods(), over every missing value (NaN: the refiner
                               // of a bundle without one)
  // The lowest RMS among the classical methods (not the HG-VAE's), and its index.
  double best_baseline_cm() const;
  int best_baseline() const;
};

// Every setting on every motion (on the model's skeleton and frame rate), masks seeded from
// (seed, setting, motion). progress(done, total) after each setting.
std::vector<GapFigure> GapExperiment(const HgvaeModel& model, const std::vector<Motion>& motions,
                                     const std::vector<GapSetting>& settings,
                                     const ImputeOptions& options, uint64_t seed,
                                     const std::function<void(int, int)>& progress = nullptr);

}  // namespace motionfork
