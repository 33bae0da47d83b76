// Classical smoothing filters over time, the baselines a denoiser has to beat (no LibTorch).
// Sequences are [frames, joints, 3] floats, metres; every coordinate is filtered on its own.
// The Gaussian smoother is in denoise_metrics.h (GaussianSmooth).
#pragma once

#include <cstdint>
#include <vector>

namespace motionfork {

// Savitzky-Golay: each value replaced by the value at its frame of the least-squares polynomial of
// degree `order` through the 2 half_window + 1 frames centred on it; near the ends, through the
// frames there are (the window is cut, the degree lowered to what they can fit). Throws
// std::invalid_argument for half_window < 1, order < 0 or a size not a multiple of joints x 3.
std::vector<float> SavitzkyGolay(const std::vector<float>& p, int joints, int half_window,
                                 int order);

// The one-euro filter (Casiez, Roussel and Vogel, CHI 2012): a causal low-pass filter whose cutoff
// rises with speed, cutoff = min_cutoff + beta |dx/dt| (Hz), the derivative itself low-passed at
// d_cutoff Hz. Little lag on fast motion, strong smoothing when still. Throws
// std::invalid_argument for fps, min_cutoff or d_cutoff <= 0, beta < 0 or a bad size.
std::vector<float> OneEuroFilter(const std::vector<float>& p, int joints, double fps,
                                 double min_cutoff, double beta, double d_cutoff = 1.0);

// The median of `values` (the mean of the middle two for an even count), which it reorders.
// Throws std::invalid_argument for no values.
double MedianInPlace(std::vector<double>* values);

// The Hampel test for outliers, per value: a value farther from the median of the 2 half_window +
// 1 frames of its coordinate centred on it (cut at the ends) than n_sigma x their scale (1.4826 x
// the median absolute deviation from that median, a Gaussian's sigma) is an outlier. Fills
// *medians with the medians [T, J, 3] and returns the flags [T, J, 3] (1: outlier). Throws
// std::invalid_argument for half_window < 1, n_sigma < 0 or a bad size.
std::vector<uint8_t> HampelOutliers(const std::vector<float>& p, int joints, int half_window,
                                    double n_sigma, std::vector<float>* medians);

// The Hampel filter, the classical tool against outliers: each outlier of HampelOutliers replaced
// by its median; n_sigma = 0 is the running median.
std::vector<float> HampelFilter(const std::vector<float>& p, int joints, int half_window,
                                double n_sigma);

}  // namespace motionfork
