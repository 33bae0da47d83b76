// Windows between the caller's layout and the network's (LibTorch, internal to imputation/).
// Caller: [B, T, N] floats, metres, root-relative coordinates without the root (frame-major, as
// pose vectors). Network: node-major [N, B, T], each coordinate normalised by the training mean
// and standard deviation stored in the bundle.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <vector>

#include "imputation/hgvae_options.h"
#include "imputation/refiner_fills.h"

namespace motionfork {

class HgvaeTensors {
 public:
  explicit HgvaeTensors(const HgvaeManifest& m);
  torch::Tensor ToNodeMajor(const float* windows, int64_t count) const;  // -> [N, B, T]
  std::vector<float> FromNodeMajor(const torch::Tensor& x) const;        // [N, B, T] -> [B, T, N]
  torch::Tensor MaskToNodeMajor(const uint8_t* missing, int64_t count) const;  // 1 = missing
  // Per value squared error in metres^2, [N, B, T].
  torch::Tensor SquaredErrorMetres(const torch::Tensor& a, const torch::Tensor& b) const;

  // The imputation refiner's input [B, T, 6N] from B windows of fills (refiner_fills.h): spline,
  // linear, rigid limb normalised, the mask as 0 / 1, the distances before and after / cap.
  torch::Tensor RefinerInput(const RefinerFills& fills) const;
  // One block of N channels of that input, in that order.
  enum class RefinerChannels { kSpline, kLinear, kRigid, kMask, kBefore, kAfter };
  torch::Tensor RefinerPart(const torch::Tensor& input, RefinerChannels part) const;
  // The refined values [.., T, N] (normalised) from the input above and the refiner's correction:
  // spline + gate * correction, the gate d^2 / (d^2 + g^2) of the distance d to the nearest
  // observed frame (g = kRefinerGateFrames): the spline is kept where the frames beside a gap pin
  // it down, the correction counts fully in long gaps.
  torch::Tensor Refined(const torch::Tensor& input, const torch::Tensor& correction) const;
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
