#include "denoise/dvae_windows.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace motionfork {

std::vector<WindowCut> CutWindows(const std::vector<int>& frames, int window, int stride) {
  std::vector<WindowCut> cuts;
  for (size_t s = 0; s < frames.size(); ++s) {
    const int n = frames[s];
    if (n < 2)
      throw std::invalid_argument("denoise: a sequence needs at least 2 frames, got " +
                                  std::to_string(n));
    if (n <= window) {
      cuts.push_back({static_cast<int>(s), 0, n, {}});
      continue;
    }
    int start = 0;
    for (; start + window < n; start += stride)
      cuts.push_back({static_cast<int>(s), start, window, {}});
    cuts.push_back({static_cast<int>(s), n - window, window, {}});
  }
  return cuts;
}

std::vector<float> WindowValues(const float* positions, int joints, WindowCut* cut) {
  const size_t stride = static_cast<size_t>(joints) * 3;
  const float* p = positions + static_cast<size_t>(cut->start) * stride;
  std::array<double, 3> mean{0, 0, 0};
  for (int t = 0; t < cut->length; ++t) {
    for (int d = 0; d < 3; ++d) mean[d] += p[t * stride + d];
  }
  for (int d = 0; d < 3; ++d) cut->root_mean[d] = static_cast<float>(mean[d] / cut->length);
  std::vector<float> out(p, p + cut->length * stride);
  for (size_t i = 0; i < out.size(); ++i) out[i] -= cut->root_mean[i % 3];
  return out;
}

std::vector<std::vector<float>> BlendWindows(const std::vector<WindowCut>& cuts,
                                             const std::vector<std::vector<float>>& values,
                                             const std::vector<int>& frames, int joints) {
  const size_t stride = static_cast<size_t>(joints) * 3;
  std::vector<std::vector<double>> sum(frames.size()), weight(frames.size());
  for (size_t s = 0; s < frames.size(); ++s) {
    sum[s].assign(frames[s] * stride, 0.0);
    weight[s].assign(frames[s], 0.0);
  }
  for (size_t w = 0; w < cuts.size(); ++w) {
    const WindowCut& c = cuts[w];
    for (int i = 0; i < c.length; ++i) {
      const double wt = std::min(i + 1, c.length - i);
      const int t = c.start + i;
      weight[c.sequence][t] += wt;
      for (size_t k = 0; k < stride; ++k) {
        sum[c.sequence][t * stride + k] += wt * (values[w][i * stride + k] + c.root_mean[k % 3]);
      }
    }
  }
  std::vector<std::vector<float>> out(frames.size());
  for (size_t s = 0; s < frames.size(); ++s) {
    out[s].resize(sum[s].size());
    for (int t = 0; t < frames[s]; ++t) {
      for (size_t k = 0; k < stride; ++k)
        out[s][t * stride + k] = static_cast<float>(sum[s][t * stride + k] / weight[s][t]);
    }
  }
  return out;
}

}  // namespace motionfork
