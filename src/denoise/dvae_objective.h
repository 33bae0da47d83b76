// Motion-DVAE objectives (LibTorch, internal to denoise/): normalisation, the prior's training
// loss on clean windows (supplement A.3, with a bone-length term in place of the SMPL term), the
// unsupervised denoising loss on noisy windows (supplement C: Student-t data term, inverse-gamma
// noise KL, latent KL, bone-length consistency) and the denoised output (D, eq. 11).
#pragma once

#include <torch/torch.h>

#include <vector>

#include "denoise/dvae_net.h"

namespace motionfork {

class DvaeTensors {
 public:
  explicit DvaeTensors(const DvaeManifest& m);
  // windows: [count, length, F] metres (window-mean-root relative) -> normalised [count, length,
  // F].
  torch::Tensor Normalise(const float* windows, int64_t count, int64_t length) const;
  std::vector<float> Denormalise(const torch::Tensor& x) const;  // -> [count, length, F] metres
  torch::Tensor BoneLengths(
      const torch::Tensor& x) const;  // normalised [B, L, F] -> metres [B, L, bones]
  const torch::Tensor& scale2() const {
    return scale2_;
  }                                                  // noise prior scale^2, normalised units [F]
  const torch::Tensor& std() const { return std_; }  // [F]
  double dof() const { return dof_; }

 private:
  torch::Tensor mean_, std_, scale2_;
  torch::Tensor child_, parent_;  // joint indices of every bone
  double dof_;
};

struct PriorTerms {
  torch::Tensor loss, nll, kl, bone, x0;  // scalars: means over the batch of per-window sums
};
// Clean windows x [B, T + 1, F] (normalised). x0 also trains the initial-state predictor.
PriorTerms PriorObjective(DvaeNet& net, const DvaeTensors& n, const torch::Tensor& x,
                          double kl_weight, double bone_weight, at::Generator gen);

struct DenoiseTerms {
  torch::Tensor loss, data, kl_z, kl_v, bone;  // scalars (means over the batch)
};
// Noisy windows y [B, T + 1, F] (normalised); latents and x0 sampled from the posterior.
DenoiseTerms DenoiseObjective(DvaeNet& net, const DvaeTensors& n, const torch::Tensor& y,
                              double kl_weight, double bone_weight, at::Generator gen);

// Denoised windows [B, T + 1, F] (normalised): the mean over `samples` posterior draws of x0, z
// and the noise variances of (v * decoder + sigma_x^2 * y) / (v + sigma_x^2); samples 0 takes
// every posterior's mean (v = beta / alpha) instead. fuse false: the decoder's frames alone.
// noise_var (optional): the noise model's beta / alpha per value [B, T + 1, F], normalised units.
torch::Tensor DenoiseOutput(DvaeNet& net, const DvaeTensors& n, const torch::Tensor& y, int samples,
                            bool fuse, at::Generator gen, torch::Tensor* noise_var = nullptr);

}  // namespace motionfork
