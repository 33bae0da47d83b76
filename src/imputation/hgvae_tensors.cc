#include "imputation/hgvae_tensors.h"

namespace motionfork {

HgvaeTensors::HgvaeTensors(const HgvaeManifest& m)
    : frames_(m.model.window), coords_(static_cast<int64_t>(m.mean.size())) {
  mean_ = torch::tensor(m.mean, torch::kFloat64).to(torch::kFloat32).view({coords_, 1, 1});
  std_ = torch::tensor(m.std, torch::kFloat64).to(torch::kFloat32).view({coords_, 1, 1});
}

torch::Tensor HgvaeTensors::ToNodeMajor(const float* windows, int64_t count) const {
  const torch::Tensor w =
      torch::from_blob(const_cast<float*>(windows), {count, frames_, coords_}, torch::kFloat32);
  return ((w.permute({2, 0, 1}) - mean_) / std_).contiguous();
}

std::vector<float> HgvaeTensors::FromNodeMajor(const torch::Tensor& x) const {
  const torch::Tensor w = (x.detach() * std_ + mean_).permute({1, 2, 0}).contiguous();
  return std::vector<float>(w.data_ptr<float>(), w.data_ptr<float>() + w.numel());
}

torch::Tensor HgvaeTensors::MaskToNodeMajor(const uint8_t* missing, int64_t count) const {
  const torch::Tensor m =
      torch::from_blob(const_cast<uint8_t*>(missing), {count, frames_, coords_}, torch::kUInt8);
  return m.permute({2, 0, 1}).to(torch::kFloat32).contiguous();
}

torch::Tensor HgvaeTensors::SquaredErrorMetres(const torch::Tensor& a,
                                               const torch::Tensor& b) const {
  return ((a - b) * std_).pow(2);
}

torch::Tensor HgvaeTensors::NormaliseFrameMajor(const float* values, int64_t count,
                                                int64_t frames) const {
  const torch::Tensor v =
      torch::from_blob(const_cast<float*>(values), {count, frames, coords_}, torch::kFloat32);
  return (v - mean_.view({1, 1, coords_})) / std_.view({1, 1, coords_});
}

torch::Tensor HgvaeTensors::DenormaliseFrameMajor(const torch::Tensor& x) const {
  return x * std_.view({1, 1, coords_}) + mean_.view({1, 1, coords_});
}

torch::Tensor HgvaeTensors::RefinerInput(const RefinerFills& f) const {
  const int64_t T = f.frames, B = static_cast<int64_t>(f.mask.size()) / (T * coords_);
  auto values = [&](const std::vector<float>& v) {
    return torch::from_blob(const_cast<float*>(v.data()), {B, T, coords_}, torch::kFloat32);
  };
  const torch::Tensor m =
      torch::from_blob(const_cast<uint8_t*>(f.mask.data()), {B, T, coords_}, torch::kUInt8)
          .to(torch::kFloat32);
  return torch::cat(
      {NormaliseFrameMajor(f.spline.data(), B, T), NormaliseFrameMajor(f.linear.data(), B, T),
       NormaliseFrameMajor(f.rigid.data(), B, T), m, values(f.before) / kRefinerGapCap,
       values(f.after) / kRefinerGapCap},
      -1);
}

torch::Tensor HgvaeTensors::RefinerPart(const torch::Tensor& in, RefinerChannels part) const {
  const int64_t k = static_cast<int64_t>(part);
  return in.slice(-1, k * coords_, (k + 1) * coords_);
}

torch::Tensor HgvaeTensors::Refined(const torch::Tensor& in,
                                    const torch::Tensor& correction) const {
  const torch::Tensor d = torch::minimum(RefinerPart(in, RefinerChannels::kBefore),
                                         RefinerPart(in, RefinerChannels::kAfter)) *
                          kRefinerGapCap;
  const torch::Tensor gate = d.pow(2) / (d.pow(2) + kRefinerGateFrames * kRefinerGateFrames);
  return RefinerPart(in, RefinerChannels::kSpline) + gate * correction;
}

}  // namespace motionfork
