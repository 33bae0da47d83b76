// A Gaussian over windows of consecutive frames (no LibTorch): the mean and covariance of the
// root-relative values of W frames in a row, [W * N], fitted on training clips. A missing value is
// estimated as its conditional mean given every value its window observes - the same coordinate's
// other frames (its velocity) and the other coordinates of the same frames (the body's shape) at
// once, the best linear estimate the training motion supports. Its use: the values a fill can
// only guess from one side (after a coordinate's last observed frame - a history's last frames,
// which a forecaster reads most - or before its first), and every value of a history no longer
// than the window, all estimated together so that the last frames move as one body.
// `hgvae fit-gaussian` measures both against the bundle's fill on held-out histories.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace motionfork {

struct WindowGaussian {
  int frames = 0;            // W
  int coords = 0;            // N
  std::vector<double> mean;  // [W * N], frame-major
  std::vector<double> cov;   // [W * N, W * N]
  long long windows = 0;     // how many windows it was fitted on
  bool empty() const { return frames == 0; }
};

// Every window of `frames` frames (every `stride`-th start) of every clip ([T, N] frame-major
// rows, N = coords). Throws std::invalid_argument when no clip holds a window or a clip's size is
// not a multiple of coords.
WindowGaussian FitWindowGaussian(const std::vector<std::vector<float>>& clips, int frames,
                                 int coords, int stride = 1);

// Which missing values the Gaussian fills.
enum class GaussianScope {
  kOneSided,     // those with no observed value of their coordinate after (or before) them
  kShortMotions  // those, and in a motion of at most W frames (a history) every missing value
                 // whose coordinate the motion observes somewhere
};
const char* GaussianScopeName(GaussianScope scope);  // "one_sided", "short_motions"
// Throws std::invalid_argument naming the accepted names.
GaussianScope ParseGaussianScope(const std::string& name);

// Per coordinate of a [T, N] mask (1 = missing), its first and last observed frame (both T when
// it is never observed).
struct ObservedSpan {
  size_t first = 0, last = 0;
};
std::vector<ObservedSpan> ObservedSpans(const std::vector<uint8_t>& mask, size_t coords);

// values, mask: [T, N] (1 = missing; missing values as some earlier stage filled them). Returns
// the values with the scope's missing values replaced by their conditional mean given the
// observed values of the last (first) min(T, W) frames - one-sided values there only where their
// coordinate is observed in those frames; every other value is kept. Throws std::invalid_argument
// on a size mismatch.
std::vector<float> FillFromWindowGaussian(const WindowGaussian& g, const std::vector<float>& values,
                                          const std::vector<uint8_t>& mask, GaussianScope scope);

// Stored as one float32 .npy array [1 + W * N, W * N]: the mean, then the covariance rows; the
// manifest records W, N and the window count (bundle/hgvae_bundle.cc).
std::string SerializeWindowGaussian(const WindowGaussian& g);
// bytes: the .npy; throws FormatError naming source_name when its shape is not [1 + W*N, W*N].
WindowGaussian ParseWindowGaussian(const std::string& bytes, int frames, int coords,
                                   long long windows, const std::string& source_name);

}  // namespace motionfork
