// Whole motions through an HG-VAE (no LibTorch): impute the missing values of a motion of any
// length, and score its windows for out-of-distribution detection.
#pragma once

#include <cstdint>
#include <vector>

#include "core/motion.h"
#include "imputation/hgvae_model.h"

namespace motionfork {

struct MotionImputation {
  Motion motion;                                  // observed values unchanged, missing ones filled
  int missing_values = 0;                         // in the input
  std::vector<int> window_starts;                 // windows that held missing values (first frame)
  std::vector<double> score_before, score_after;  // per such window
};

// The motion must be on the model's skeleton and frame rate (root first, metres); `missing` is
// [T, J, 3], 1 = missing. Windows start at 0, W, 2W, ... and one more ends at the last frame;
// frames two windows cover get the mean of both. Missing values start where options.start says
// (the mean pose, or an interpolation over the whole motion). Throws std::invalid_argument for a
// motion shorter than the window, a missing root value (poses are root-relative; names the frame),
// a window with every value missing (names its frames), or a mask of the wrong size.
MotionImputation ImputeMotion(const HgvaeModel& model, const Motion& motion,
                              const std::vector<uint8_t>& missing, const ImputeOptions& options,
                              int class_index = -1);

struct WindowScore {
  int start = 0;  // first frame
  double score = 0;
  bool out_of_distribution = false;
};

// Windows starting every `stride` frames (and one ending at the last frame).
std::vector<WindowScore> ScoreMotion(const HgvaeModel& model, const Motion& motion, int stride,
                                     int class_index = -1);

// The model's training mean pose [J, 3] about a zero root (a fallback for values never observed).
std::vector<float> TrainingMeanPose(const HgvaeModel& model);

// Start frames of windows of `window` frames every `stride` frames covering 0..frames-1.
std::vector<int> CoveringWindowStarts(int frames, int window, int stride);

}  // namespace motionfork
