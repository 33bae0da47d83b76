// The Motion-DVAE network (LibTorch), after the supplement's A.1-A.2 and E.1, on joint positions.
//
// Sequences are batch-first [B, T + 1, F]: frame 0 is the initial pose x0, frames 1..T are
// generated; F = joints x 3 normalised values.
//
// Generative model: h_0 = d_ini(x0); h_t = LSTM(h_{t-1}, z_t) (one LSTM for both h^x and h^z);
// p(z_t | z_<t, x0) = N(d_z(h_{t-1})); p(x_t | z_<=t, x0) = N(d_x(h_t), exp(x_logvar)) with a
// learned variance per value (the paper fixes it to the identity: positions in metres need a
// scale). Inference: h^data_t = backward LSTM over x_t..x_T; h^lat_0 = e_ini(x0), h^lat_t =
// LSTMCell( h^lat_{t-1}, z_t); q(z_t | .) = N(e_glob([h^lat_{t-1}, h^data_t])). Denoising adds the
// initial-state predictor q(x0 | y) = N(e_x0(backward LSTM over y_0..y_T)) and the noise predictor
// q(v_t) = InvGamma(e_b([h_t, y_t, y_t - mean_t])) per value (the residual is an input besides the
// paper's h_t and y_t: the predictor would otherwise have to rebuild it). Every MLP: Linear,
// GroupNorm, ReLU, Linear, GroupNorm, ReLU, Linear.
#pragma once

#include <torch/torch.h>

#include <utility>
#include <vector>

#include "denoise/dvae_options.h"
#include "refine/refiner_net.h"

namespace motionfork {

class DvaeMlpImpl : public torch::nn::Module {
 public:
  DvaeMlpImpl(int64_t in, int64_t hidden, int64_t out, int64_t groups);
  torch::Tensor forward(const torch::Tensor& x);  // [..., in] -> [..., out]

  torch::nn::Linear l1{nullptr}, l2{nullptr}, l3{nullptr};
  torch::nn::GroupNorm g1{nullptr}, g2{nullptr};
};
TORCH_MODULE(DvaeMlp);

struct DvaePass {
  torch::Tensor x0;                        // [B, F] the initial pose used
  torch::Tensor mean;                      // [B, T, F] decoder means of frames 1..T
  torch::Tensor hidden;                    // [B, T + 1, H] decoder states h_0..h_T
  torch::Tensor z;                         // [B, T, Z]
  torch::Tensor post_mean, post_logvar;    // [B, T, Z]
  torch::Tensor prior_mean, prior_logvar;  // [B, T, Z]
  torch::Tensor kl;                        // [B] sum over frames and latents
};

// Inverse-gamma parameters of the noise variances, per value [B, T + 1, F], in metres^2.
struct DvaeNoise {
  torch::Tensor alpha, beta;
};

class DvaeNetImpl : public torch::nn::Module {
 public:
  // refiner: the denoising refiner's settings (channels 0: none).
  DvaeNetImpl(const DvaeOptions& options, int64_t values, const RefinerOptions& refiner = {});

  // Encoder (from frames 1..T of seq) and decoder; x0 is the initial pose. sample: z from the
  // posterior with gen, else its means.
  DvaePass Run(const torch::Tensor& seq, const torch::Tensor& x0, bool sample,
               c10::optional<at::Generator> gen);
  // q(x0 | y): (mean, log-variance) [B, F] from the whole (noisy) sequence.
  std::pair<torch::Tensor, torch::Tensor> InitialState(const torch::Tensor& seq);
  // Noise predictor: y [B, T + 1, F] against the decoder's frames [B, T + 1, F] (x0, means), with
  // the decoder states; prior_beta_scale: the prior's scale^2 in normalised units per value [F],
  // the centre of the predicted beta / alpha at initialisation.
  DvaeNoise NoiseVariances(const torch::Tensor& y, const torch::Tensor& frames,
                           const torch::Tensor& hidden, const torch::Tensor& scale2);

  // Decoder only: sequences from the prior given x0 [B, F]: frames 1..T [B, T, F] (means).
  torch::Tensor Generate(const torch::Tensor& x0, int64_t frames, bool sample_latents,
                         at::Generator gen);

  // Parameters the unsupervised denoising training learns (encoder, initial state, noise), and
  // the ones it keeps (decoder, prior, output variance).
  std::vector<torch::Tensor> EncoderParameters();
  std::vector<torch::Tensor> DecoderParameters();

  const DvaeOptions& options() const { return options_; }

  torch::Tensor x_logvar;  // [F] log-variance of p(x_t | ...), normalised units
  // The denoising refiner (null when the manifest has none): normalised noisy windows [B, T, F]
  // -> their correction; trained apart from the rest (`dvae refine`).
  TemporalRefiner refiner{nullptr};

 private:
  DvaeOptions options_;
  int64_t values_;
  // generative
  DvaeMlp d_ini{nullptr}, d_x{nullptr}, d_z{nullptr};
  torch::nn::LSTM dec_lstm{nullptr};
  // inference
  DvaeMlp e_ini{nullptr}, e_glob{nullptr};
  torch::nn::LSTM e_data{nullptr};
  torch::nn::LSTMCell e_lat{nullptr};
  // denoising
  torch::nn::LSTM r_h{nullptr};
  DvaeMlp e_x0{nullptr}, e_b{nullptr};
};
TORCH_MODULE(DvaeNet);

// KL(N(m1, e^l1) || N(m2, e^l2)) elementwise.
torch::Tensor GaussianKl(const torch::Tensor& m1, const torch::Tensor& l1, const torch::Tensor& m2,
                         const torch::Tensor& l2);
// KL(InvGamma(a, b) || InvGamma(a0, b0)) elementwise.
torch::Tensor InverseGammaKl(const torch::Tensor& a, const torch::Tensor& b, double a0,
                             const torch::Tensor& b0);

int DvaeValues(const DvaeManifest& m);  // joints x 3
// The network a manifest describes (untrained).
DvaeNet BuildDvaeNet(const DvaeManifest& m);

}  // namespace motionfork
