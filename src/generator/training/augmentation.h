// Varying the generator's training windows at random (AugmentationOptions, config section
// `augmentation`; no LibTorch): mirrored, resized, played faster or slower, and a noisy history
// for the network to read. A window's pseudo multimodal futures get the same mirror, size and
// speed as the window they serve.
//
// Poses are root-relative without the root ([frames, N, 3], node n = skeleton joint n + 1), in the
// data's axes or the body's frame, as TrainingWindows::Gather gives them.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/skeleton.h"
#include "generator/model/training_options.h"

namespace motionfork {

struct TrainingWindows;

// One window's draw.
struct WindowAugmentation {
  bool mirror = false;
  double scale = 1;  // body size factor
  double speed = 1;  // playback factor (TrainingWindows::Gather's)
};

// Draws `count` windows' augmentations from `rng`, in order; every key the options switch on
// takes one draw per window whether or not it changes it, so that a step's draws depend only on
// the options and the seed (every training worker draws the whole step). Options that are off
// take no draws: a run without augmentation draws what it drew before the options existed.
std::vector<WindowAugmentation> DrawAugmentations(const AugmentationOptions& options, int count,
                                                  std::mt19937_64& rng);

// How a pose is mirrored: each node's partner (itself when unpaired) and the coordinate negated.
struct MirrorPlan {
  std::vector<int> partner;  // [N]
  int axis = 0;              // 0 x, 1 y, 2 z
};

// The skeleton's left/right pairs (Skeleton::Mirror) as nodes, and the axis the training windows'
// hip lines lie along: the coordinate with the largest mean |left - right| over every window's
// last history frame, for the heading pair (core/heading.h's HeadingNodes). Reflecting that axis
// keeps the heading of a window whose hips lie along it: every window in the body's frame (each
// turned so that they do), in the data's axes the windows that face the data's usual way (the
// others come out mirrored and facing another way, still real motion). Throws
// std::invalid_argument naming the skeleton when it names no left/right pair.
MirrorPlan MakeMirrorPlan(const Skeleton& skeleton, const TrainingWindows& data);

// Mirrors poses [frames, N, 3] in place: partners exchanged, plan.axis negated.
void MirrorPoses(const MirrorPlan& plan, int frames, float* poses);

// Scales `count` floats in place by `factor`.
void ScalePoses(double factor, size_t count, float* poses);

// Gaussian noise of standard deviation `sd` (metres) added to `count` floats (whole 3-vectors) in
// place, drawn from `rng` by core/motion_noise.h's gaussian noise (count draws, none when sd is 0).
void AddNoise(double sd, size_t count, std::mt19937_64& rng, float* values);

}  // namespace motionfork
