// Synthetic corruptions of joint positions, the noise of estimated (video) motion: the inputs of
// denoising experiments and of the denoiser's unsupervised training.
//
//   gaussian:S     every value + N(0, S^2), S in metres
//   outliers:P,S   heavy-tailed: each joint of each frame, with probability P, is displaced by
//                  N(0, S^2) per axis (the rest untouched)
//   jitter:S       every frame, the whole body shifts by N(0, S^2) per axis (the same offset for
//                  every joint: the frame-to-frame wobble of monocular estimates)
#pragma once

#include <cstdint>
#include <random>
#include <string>

#include "core/motion.h"

namespace motionfork {

struct NoiseSpec {
  enum class Kind { kGaussian, kOutliers, kJitter };
  Kind kind = Kind::kGaussian;
  double sigma = 0;  // metres
  double rate = 0;   // outliers: probability per joint and frame
  std::string text;  // as parsed
};

// Throws std::invalid_argument naming the spec and the expected forms.
NoiseSpec ParseNoiseSpec(const std::string& text);

// Adds the noise to positions [frames, joints, 3] in place.
void AddNoise(const NoiseSpec& spec, float* positions, int frames, int joints,
              std::mt19937_64& rng);
// A noisy copy; the same seed gives the same noise.
Motion AddNoise(const Motion& motion, const NoiseSpec& spec, uint64_t seed);

}  // namespace motionfork
