// Figures of denoising experiments and a classical baseline (no LibTorch). Sequences are
// [frames, joints, 3] floats, metres.
#pragma once

#include <vector>

namespace motionfork {

// Mean over frames and joints of the Euclidean distance, metres.
double MeanJointError(const std::vector<float>& a, const std::vector<float>& b);
// Mean over frames and joints of |x[t+1] - 2 x[t] + x[t-1]| * fps^2, m/s^2 (the paper's
// plausibility figure: a denoiser's should be 0.5x - 2x the clean motion's).
double MeanAcceleration(const std::vector<float>& p, int joints, double fps);
// Baseline: every coordinate smoothed over time by a Gaussian of sigma frames (edges renormalised).
std::vector<float> GaussianSmooth(const std::vector<float>& p, int joints, double sigma_frames);

}  // namespace motionfork
