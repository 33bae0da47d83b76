#include "denoise/dvae_objective.h"

#include <cmath>
#include <map>
#include <stdexcept>

#include "denoise/dvae_net.h"

namespace motionfork {

namespace {

constexpr double kLog2Pi = 1.8378770664093453;
constexpr double kCm2 = 1e-4;  // bone terms are per cm^2

torch::Tensor Sample(const torch::Tensor& mean, const torch::Tensor& logvar, at::Generator gen) {
  return mean + torch::exp(0.5 * logvar) * at::normal(0.0, 1.0, mean.sizes(), gen, mean.options());
}

}  // namespace

DvaeTensors::DvaeTensors(const DvaeManifest& m) : dof_(m.noise_prior.dof) {
  const int64_t F = DvaeValues(m);
  mean_ = torch::tensor(std::vector<float>(m.mean.begin(), m.mean.end()));
  std_ = torch::tensor(std::vector<float>(m.std.begin(), m.std.end()));
  if (mean_.numel() != F || std_.numel() != F)
    throw std::invalid_argument("Motion-DVAE: normalisation has the wrong size");
  scale2_ = (m.noise_prior.scale / std_).pow(2);
  std::map<std::string, int64_t> index;
  for (size_t j = 0; j < m.skeleton.joint_names.size(); ++j)
    index[m.skeleton.joint_names[j]] = static_cast<int64_t>(j);
  std::vector<int64_t> child, parent;
  for (size_t j = 0; j < m.skeleton.parent_names.size(); ++j) {
    if (m.skeleton.parent_names[j].empty()) continue;
    child.push_back(static_cast<int64_t>(j));
    parent.push_back(index.at(m.skeleton.parent_names[j]));
  }
  child_ = torch::tensor(child);
  parent_ = torch::tensor(parent);
}

torch::Tensor DvaeTensors::Normalise(const float* windows, int64_t count, int64_t length) const {
  const int64_t F = mean_.numel();
  const torch::Tensor x =
      torch::from_blob(const_cast<float*>(windows), {count, length, F}, torch::kFloat32);
  return (x - mean_) / std_;
}

std::vector<float> DvaeTensors::Denormalise(const torch::Tensor& x) const {
  const torch::Tensor m = (x * std_ + mean_).contiguous();
  return std::vector<float>(m.data_ptr<float>(), m.data_ptr<float>() + m.numel());
}

torch::Tensor DvaeTensors::BoneLengths(const torch::Tensor& x) const {
  const torch::Tensor p = (x * std_ + mean_).reshape({x.size(0), x.size(1), -1, 3});
  return (p.index_select(2, child_) - p.index_select(2, parent_)).norm(2, -1);
}

PriorTerms PriorObjective(DvaeNet& net, const DvaeTensors& n, const torch::Tensor& x,
                          double kl_weight, double bone_weight, at::Generator gen) {
  PriorTerms t;
  const torch::Tensor x0 = x.select(1, 0);
  const DvaePass p = net->Run(x, x0, /*sample=*/true, gen);
  const torch::Tensor target = x.slice(1, 1), lv = net->x_logvar;
  t.nll = (0.5 * (kLog2Pi + lv + (target - p.mean).pow(2) * torch::exp(-lv))).sum({1, 2}).mean();
  t.kl = p.kl.mean();
  t.bone = ((n.BoneLengths(p.mean) - n.BoneLengths(target)).pow(2) / kCm2).sum({1, 2}).mean();
  // The initial-state predictor learns on clean windows too: a start for denoising.
  const auto [m0, lv0] = net->InitialState(x);
  t.x0 = (0.5 * (kLog2Pi + lv0 + (x0 - m0).pow(2) * torch::exp(-lv0))).sum(1).mean();
  t.loss = t.nll + kl_weight * t.kl + bone_weight * t.bone + t.x0;
  return t;
}

namespace {

struct NoisyPass {
  DvaePass pass;
  torch::Tensor frames;  // [B, T + 1, F]: x0 and the decoder's means
  DvaeNoise noise;
};

NoisyPass RunNoisy(DvaeNet& net, const DvaeTensors& n, const torch::Tensor& y, bool sample,
                   at::Generator gen) {
  NoisyPass r;
  const auto [m0, lv0] = net->InitialState(y);
  const torch::Tensor x0 = sample ? Sample(m0, lv0, gen) : m0;
  r.pass = net->Run(y, x0, sample, gen);
  r.frames = torch::cat({x0.unsqueeze(1), r.pass.mean}, 1);
  r.noise = net->NoiseVariances(y, r.frames, r.pass.hidden, n.scale2());
  return r;
}

}  // namespace

DenoiseTerms DenoiseObjective(DvaeNet& net, const DvaeTensors& n, const torch::Tensor& y,
                              double kl_weight, double bone_weight, at::Generator gen) {
  DenoiseTerms t;
  const NoisyPass r = RunNoisy(net, n, y, /*sample=*/true, gen);
  const torch::Tensor& a = r.noise.alpha;
  const torch::Tensor& b = r.noise.beta;
  // E_q(v)[-log N(y; frames, v)] with E[1/v] = a / b and E[log v] = log b - digamma(a).
  t.data = (0.5 * (kLog2Pi + torch::log(b) - torch::digamma(a) + (a / b) * (y - r.frames).pow(2)))
               .sum({1, 2})
               .mean();
  const double a0 = n.dof() / 2;
  t.kl_v = InverseGammaKl(a, b, a0, a0 * n.scale2()).sum({1, 2}).mean();
  t.kl_z = r.pass.kl.mean();
  const torch::Tensor len = n.BoneLengths(r.frames);
  t.bone = ((len - len.mean(1, /*keepdim=*/true)).pow(2) / kCm2).sum({1, 2}).mean();
  t.loss = t.data + t.kl_v + kl_weight * t.kl_z + bone_weight * t.bone;
  return t;
}

torch::Tensor DenoiseOutput(DvaeNet& net, const DvaeTensors& n, const torch::Tensor& y, int samples,
                            bool fuse, at::Generator gen, torch::Tensor* noise_var) {
  const torch::Tensor sx2 = torch::exp(net->x_logvar);
  if (samples <= 0) {
    const NoisyPass r = RunNoisy(net, n, y, /*sample=*/false, gen);
    const torch::Tensor v = r.noise.beta / r.noise.alpha;
    if (noise_var) *noise_var = v;
    return fuse ? (v * r.frames + sx2 * y) / (v + sx2) : r.frames;
  }
  const int64_t B = y.size(0);
  const torch::Tensor ys = y.repeat({samples, 1, 1});
  const NoisyPass r = RunNoisy(net, n, ys, /*sample=*/true, gen);
  const torch::Tensor v = r.noise.beta / at::_standard_gamma(r.noise.alpha, gen).clamp_min(1e-12);
  const torch::Tensor fused = fuse ? (v * r.frames + sx2 * ys) / (v + sx2) : r.frames;
  if (noise_var)
    *noise_var = (r.noise.beta / r.noise.alpha).reshape({samples, B, y.size(1), y.size(2)}).mean(0);
  return fused.reshape({samples, B, y.size(1), y.size(2)}).mean(0);
}

}  // namespace motionfork
