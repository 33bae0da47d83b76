#include "refine/refiner_net.h"

#include <algorithm>
#include <string>

namespace motionfork {

namespace {

torch::nn::Conv1d Conv(int64_t in, int64_t out, int64_t kernel, int64_t dilation,
                       int64_t groups = 1) {
  return torch::nn::Conv1d(torch::nn::Conv1dOptions(in, out, kernel)
                               .dilation(dilation)
                               .groups(groups)
                               .padding(dilation * (kernel / 2))
                               .padding_mode(torch::kReplicate));
}

}  // namespace

TemporalRefinerImpl::TemporalRefinerImpl(const RefinerOptions& o, int64_t in, int64_t out) {
  ValidateRefinerOptions(o, "refiner");
  const int64_t C = o.channels;
  const int64_t R = o.linear_reach;
  linear = register_module("linear", Conv(out, out, 2 * R + 1, 1, out));
  input = register_module("input", Conv(in, C, 3, 1));
  for (size_t k = 0; k < o.dilations.size(); ++k) {
    dilated.push_back(
        register_module("dilated" + std::to_string(k), Conv(C, C, 3, o.dilations[k])));
    mix.push_back(register_module("mix" + std::to_string(k), Conv(C, C, 1, 1)));
  }
  output = register_module("output", Conv(C, out, 1, 1));
  torch::NoGradGuard no_grad;
  output->weight.zero_();
  output->bias.zero_();
  // The linear path starts as a Gaussian smoother of sigma R / 4 frames (or at zero) (its
  // correction: the smoothed motion minus the motion), the classical filter the refiner is to beat.
  const torch::Tensor k = torch::arange(-R, R + 1, torch::kFloat32);
  torch::Tensor taps = torch::exp(-0.5 * (k * 4.0 / std::max<int64_t>(R, 1)).pow(2));
  taps = taps / taps.sum();
  taps.index_put_({R}, taps.index({R}) - 1.0);
  linear->weight.copy_(taps.expand({out, 1, 2 * R + 1}));
  if (!o.smooth_start) linear->weight.zero_();
  linear->bias.zero_();
}

torch::Tensor TemporalRefinerImpl::forward(const torch::Tensor& x) {
  const torch::Tensor xt = x.transpose(1, 2);
  torch::Tensor h = input(xt);
  for (size_t k = 0; k < dilated.size(); ++k)
    h = h + mix[k](torch::relu(dilated[k](torch::relu(h))));
  return (linear(xt.slice(1, 0, linear->options.in_channels())) + output(torch::relu(h)))
      .transpose(1, 2);
}

}  // namespace motionfork
