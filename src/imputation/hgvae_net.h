// The HG-VAE network (LibTorch): hierarchical graph-convolutional VAE over motion windows.
//
// Layout: node-major [N, B, F] (graph nodes, windows, features) as in the generator, so every
// product is one matrix multiplication. The observable graph has one node per coordinate (joints
// x 3) with the window's DCT coefficients as features; stochastic level l has nodes_l x
// features_l latents, level 0 being one global node.
//
// Encoder (bottom-up): graph-conv from the coefficients to the bottom level, residual blocks,
// then graph-convs that contract the nodes level by level, keeping each level's activations.
// Decoder (top-down): a deterministic path of `width` features expanded level by level; at each
// level a prior head p(z_l | z<l) reads the path, a posterior head q(z_l | x, z<l) reads the path
// and the encoder's activations, and the sampled z_l is added back into the path. The output head
// gives the mean and log-variance of p(x | z) per coordinate and frame.
#pragma once

#include <torch/torch.h>

#include <vector>

#include "imputation/hgvae_options.h"
#include "refine/refiner_net.h"

namespace motionfork {

// GCL without activation: y = S (x W) + b with S [Nout, Nin], W [Fin, Fout], b [Nout, 1, Fout].
class HgvaeGraphConvImpl : public torch::nn::Module {
 public:
  HgvaeGraphConvImpl(int64_t in_nodes, int64_t out_nodes, int64_t in_features,
                     int64_t out_features);
  torch::Tensor forward(const torch::Tensor& x);  // [Nin, B, Fin] -> [Nout, B, Fout]

  torch::Tensor adjacency, weight, bias;
};
TORCH_MODULE(HgvaeGraphConv);

// GCB with a ReZero residual: x + alpha * gelu(S2 gelu(S1 x W1 + b1) W2 + b2), alpha starting at 0.
// (The paper's eq. 5 writes the weight on the other term; its released code weights the branch,
// as ReZero does, which keeps deep stacks the identity at initialisation.)
class HgvaeBlockImpl : public torch::nn::Module {
 public:
  HgvaeBlockImpl(int64_t nodes, int64_t features);
  torch::Tensor forward(const torch::Tensor& x);

  HgvaeGraphConv first{nullptr}, second{nullptr};
  torch::Tensor alpha;
};
TORCH_MODULE(HgvaeBlock);

// One forward pass's results. Per level l: prior (mean, log-variance) and posterior (mean,
// log-variance), each [n_l, B, f_l]; `z` the latents used.
struct HgvaeOutput {
  torch::Tensor x_mean, x_logvar;  // [N, B, T] in the time domain (normalised coordinates)
  std::vector<torch::Tensor> prior_mean, prior_logvar, post_mean, post_logvar, z;
  torch::Tensor kl;                      // [B]: sum over the stochastic levels
  std::vector<torch::Tensor> kl_levels;  // per level [B] (zeros for levels that are off)
};

// How latents are chosen in a pass.
enum class LatentMode {
  kSample,         // z_l ~ q(z_l | x, z<l) (training)
  kPosteriorMean,  // z_l = posterior mean (scores, imputation: deterministic)
};

class HgvaeNetImpl : public torch::nn::Module {
 public:
  // num_coords: nodes of the full graph; frames: window length; classes: one-hot size (0 = none).
  // options.levels must be resolved (no 0 nodes).
  // refiner: the imputation refiner's settings (channels 0: none).
  HgvaeNetImpl(const HgvaeOptions& options, int64_t num_coords, int64_t frames, int64_t classes,
               const RefinerOptions& refiner = {});

  // The imputation refiner (null when the manifest has none): normalised fills [B, T,
  // kRefinerChannels * N] (HgvaeTensors::RefinerInput) -> the spline's correction [B, T, N];
  // trained apart from the rest (`hgvae refine`).
  static constexpr int64_t kRefinerChannels = 6;
  TemporalRefiner refiner{nullptr};

  // x: normalised windows, node-major [N, B, T]; labels: one-hot [B, classes] or undefined (all
  // zero = no class). gen: for kSample.
  HgvaeOutput forward(const torch::Tensor& x, const torch::Tensor& labels, LatentMode mode,
                      c10::optional<at::Generator> gen = c10::nullopt);

  // Decoder only: latents from the prior (sampled with `gen` when sample_latents, else its
  // means), output mean [N, B, T].
  torch::Tensor Generate(int64_t count, const torch::Tensor& labels, bool sample_latents,
                         at::Generator gen);

  // log N(x | mean, exp(logvar)) summed over nodes and frames, per window [B].
  static torch::Tensor GaussianLogLik(const torch::Tensor& x, const torch::Tensor& mean,
                                      const torch::Tensor& logvar);

  // The paper's posterior score per window [B]: sum over stochastic levels of
  // log N(post_mean_l | prior_mean_l, prior_var_l).
  torch::Tensor PosteriorScore(const HgvaeOutput& out) const;
  // Either window score [B] of a posterior-mean pass `out` of x: kPosterior = PosteriorScore,
  // kJoint = PosteriorScore + log p(x | posterior means).
  torch::Tensor Score(const torch::Tensor& x, const HgvaeOutput& out, ImputeObjective which) const;

  int64_t num_levels() const { return static_cast<int64_t>(options_.levels.size()); }
  bool stochastic(int64_t level) const;
  const torch::Tensor& dct() const { return dct_; }

 private:
  torch::Tensor TopDown(const std::vector<torch::Tensor>* encoded, const torch::Tensor& labels,
                        int64_t batch, LatentMode mode, bool from_prior,
                        c10::optional<at::Generator> gen, HgvaeOutput* out);

  // Path at the full graph -> (mean [N, B, T] in frames, log-variance [N, B, T]).
  std::pair<torch::Tensor, torch::Tensor> Output(const torch::Tensor& path);

  HgvaeOptions options_;
  int64_t num_coords_, frames_, classes_;
  torch::Tensor dct_;  // [T, T] orthonormal DCT-II (buffer, not trained)
  HgvaeGraphConv enc_input{nullptr};
  std::vector<HgvaeGraphConv> enc_contract;       // level l+1 -> l, for l = L-2 .. 0 (index l)
  std::vector<torch::nn::Sequential> enc_blocks;  // per level
  HgvaeGraphConv dec_top{nullptr};                // z0 (+ one-hot) -> path
  std::vector<HgvaeGraphConv> dec_expand;         // path: level l-1 -> l (index l >= 1)
  std::vector<HgvaeGraphConv> prior_head, post_head, z_in;  // per level (prior_head[0] unused)
  std::vector<torch::nn::Sequential> dec_blocks;            // per level
  HgvaeGraphConv out_head{nullptr};  // path -> T means (+ T log-variances if predicted)
  torch::Tensor out_logvar;          // [N, 1, T] learned log-variance (not predicted)
};
TORCH_MODULE(HgvaeNet);

// Nodes of the full graph for a manifest: 3 per non-root joint.
int HgvaeCoords(const HgvaeManifest& m);
// The network a manifest describes (untrained).
HgvaeNet BuildHgvaeNet(const HgvaeManifest& m);

}  // namespace motionfork
