#include "refine/refiner_windows.h"

#include <algorithm>
#include <vector>

namespace motionfork {

torch::Tensor RefineInWindows(TemporalRefiner& net, const torch::Tensor& input, int window,
                              int stride) {
  const int64_t T = input.size(0), L = std::min<int64_t>(window, T);
  std::vector<int64_t> starts;
  for (int64_t s = 0; s + L <= T; s += stride) starts.push_back(s);
  if (starts.back() + L < T) starts.push_back(T - L);
  const torch::Tensor weight =
      torch::minimum(torch::arange(1, L + 1), torch::arange(L, 0, -1)).to(torch::kFloat32);
  torch::Tensor sum, total = torch::zeros({T});
  constexpr size_t kBatch = 256;
  for (size_t b0 = 0; b0 < starts.size(); b0 += kBatch) {
    const size_t b1 = std::min(starts.size(), b0 + kBatch);
    std::vector<torch::Tensor> windows;
    for (size_t k = b0; k < b1; ++k) windows.push_back(input.slice(0, starts[k], starts[k] + L));
    const torch::Tensor out = net->forward(torch::stack(windows));  // [B, L, out]
    if (!sum.defined()) sum = torch::zeros({T, out.size(2)});
    for (size_t k = b0; k < b1; ++k) {
      sum.slice(0, starts[k], starts[k] + L) +=
          out[static_cast<int64_t>(k - b0)] * weight.unsqueeze(1);
      total.slice(0, starts[k], starts[k] + L) += weight;
    }
  }
  return sum / total.unsqueeze(1);
}

}  // namespace motionfork
