// Windows between the caller's layout and the network's (LibTorch, internal to imputation/).
// Caller: [B, T, N] floats, metres, root-relative coordinates without the root (frame-major, as
// pose vectors). Network: node-major [N, B, T], each coordinate normalised by the training mean
// and standard deviation stored in the bundle.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <vector>

#include "imputation/hgvae_options.h"

namespace motionfork {

class HgvaeTensors {
 public:
  explicit HgvaeTensors(const HgvaeManifest& m);
  torch::Tensor ToNodeMajor(const float* windows, int64_t count) const;  // -> [N, B, T]
  std::vector<float> FromNodeMajor(const torch::Tensor& x) const;        // [N, B, T] -> [B, T, N]
  torch::Tensor MaskToNodeMajor(const uint8_t* missing, int64_t count) const;  // 1 = missing
  // Per value squared error in metres^2, [N, B, T].
  torch::Tensor SquaredErrorMetres(const torch::Tensor& a, const torch::Tensor& b) const;

  // The imputation refiner's input [B, T, 4N] from fills laid out [B, T, N] each (metres) and the
  // mask: spline, linear, rigid limb normalised, then the mask as 0 / 1.
  torch::Tensor RefinerInput(const float* spline, const float* linear, const float* rigid,
                             const uint8_t* mask, int64_t count, int64_t frames) const;
  // [B, T, N] normalised <-> metres, frame-major.
  torch::Tensor NormaliseFrameMajor(const float* values, int64_t count, int64_t frames) const;
  torch::Tensor DenormaliseFrameMajor(const torch::Tensor& x) const;

  int64_t frames() const { return frames_; }
  int64_t coords() const { return coords_; }

 private:
  int64_t frames_, coords_;
  torch::Tensor mean_, std_;  // [N, 1, 1]
};

}  // namespace motionfork
