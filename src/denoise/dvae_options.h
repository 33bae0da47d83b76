// Motion-DVAE settings (configs/models/dvae_*.yaml; bundles' dvae.yaml). Plain structs, no
// LibTorch.
//
// The model follows the Motion-DVAE supplement (../shared/seeds/motion-dvae-supplement.txt) on
// joint positions instead of SMPL parameters: a pose is every joint's position relative to the
// window's mean root position (joints x 3 values, metres), so the root's path is denoised too.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "core/skeleton.h"
#include "denoise/refiner_blend.h"
#include "refine/refiner_options.h"

namespace motionfork {

struct DvaeOptions {
  int window = 30;    // frames per training window: the initial pose x0 and 29 more (1 s at 30 Hz)
  int hidden = 1024;  // LSTM hidden state (paper: 1024)
  int latent = 48;    // z_t per frame (paper: 48)
  int mlp_hidden = 512;  // width of the MLPs' two hidden layers
  int groups = 16;       // group-norm groups in every MLP (paper: 16)
};

// Training the motion prior on clean windows.
struct DvaeTrainOptions {
  int epochs = 200;               // paper: 200
  int windows_per_epoch = 20000;  // random training windows per epoch
  int batch_size = 64;            // paper: 64
  double learning_rate = 1e-3;    // Adam (the paper's Adamax is not in LibTorch's C++ API)
  double lr_decay = 1.0;          // learning rate x this after every epoch
  double grad_clip = 10;          // gradient-norm clip
  int kl_anneal_epochs =
      50;  // KL weight rises linearly from kl_start to 1 (paper: first 50 epochs)
  double kl_start = 1e-3;
  double bone_weight = 1.0;  // bone-length term (in place of the paper's SMPL mesh term), per cm^2
  double held_out_share = 0.05;  // training clips held out for per-epoch figures
  int held_out_windows = 1000;
  uint64_t seed = 0;
  int threads = 1;
};

// Unsupervised denoising training ("regression mode"): the encoder, the initial-state predictor
// and the noise predictor learn on noisy windows only; decoder and prior stay fixed.
struct DvaeFinetuneOptions {
  int epochs = 30;
  int windows_per_epoch = 20000;
  int batch_size = 64;
  double learning_rate = 3e-4;
  double grad_clip = 10;
  int kl_anneal_epochs = 5;
  double kl_start = 0.1;
  double bone_weight = 1.0;  // bone-length consistency of the output within a window, per cm^2
  std::vector<std::string> noise = {
      "gaussian:0.02", "gaussian:0.05", "gaussian:0.10", "outliers:0.1,0.3",
      "jitter:0.05"};  // corruptions of the training windows, one per window
  int patience = 10;   // stop when the held-out loss has not improved for this many epochs
  uint64_t seed = 1;
  int threads = 1;
};

// Noise prior: v ~ InvGamma(dof / 2, dof / 2 * scale^2) per joint, axis and frame, i.e. a
// Student-t likelihood with `dof` degrees of freedom and scale `scale` metres.
struct DvaeNoisePrior {
  double dof = 4.0;
  double scale = 0.05;
};

// regression: one pass of the fine-tuned encoder; optimisation: Adam steps on the sequence's own
// loss first; refiner: the bundle's temporal refiner (supervised, refine/refiner_net.h) corrects
// the noisy motion itself.
enum class DenoiseMode { kRegression, kOptimisation, kRefiner };
// Their names in configs, bundles and flags (ParseDenoiseMode also takes "optimization").
inline constexpr EnumName<DenoiseMode> kDenoiseModeNames[] = {
    {DenoiseMode::kRegression, "regression"},
    {DenoiseMode::kOptimisation, "optimisation"},
    {DenoiseMode::kRefiner, "refiner"}};
const char* ToString(DenoiseMode mode);
DenoiseMode ParseDenoiseMode(const std::string& text);  // "regression" | "optimisation"

struct DenoiseOptions {
  DenoiseMode mode = DenoiseMode::kRegression;
  int iterations = 50;  // optimisation mode: Adam steps on the sequence (paper: 50 on AMASS)
  double learning_rate = 3e-4;  // optimisation mode
  double bone_weight = 0.1;  // optimisation mode: bone-length constancy per cm^2 (as fine-tuning)
  // true: the paper's eq. 11, each value (v * decoder + sigma_x^2 * y) / (v + sigma_x^2), which
  // keeps some of the input's frame-to-frame noise; false: the decoder's frames only (smoother).
  bool fuse = true;
  int samples = 4;  // posterior draws averaged (x0, z, noise variances); 0 = posterior means
  int stride = 15;  // windows overlap by window - stride frames
  uint64_t seed = 0;
  // Refiner mode: blend the output with the input by the bundle's refiner_blend (refiner_blend.h);
  // false: the refiner's output as it is (what the blend is fitted on). Not a bundle key.
  bool refiner_blend = true;
};

// Command-line overrides of a bundle's DenoiseOptions; unset fields ("" or < 0) keep the bundle's
// value.
struct DenoiseOverrides {
  std::string mode;  // "regression" | "optimisation" | ""
  int iterations = -1, samples = -1;
  int64_t seed = -1;
  std::string blend;  // "fused" | "decoder" | ""
  DenoiseOptions Apply(DenoiseOptions o) const;
};

// Training the denoising refiner (`dvae refine`): clean training windows corrupted by one of
// `noise` at a random level (each spec's sigma and rate are the upper ends: the level is a uniform
// share of them), or left clean with probability clean_share; the refiner learns to give the clean
// window back: loss = mean joint error (cm) + accel_weight x mean joint error of the accelerations
// (second differences, cm per frame^2; what keeps noise from surviving as jerk).
struct DvaeRefinerConfig {
  RefinerOptions model = {128};
  RefinerTrainOptions training;
  std::vector<std::string> noise = {"gaussian:0.12", "outliers:0.15,0.6", "jitter:0.12"};
  double clean_share = 0.1;
  double accel_weight = 0;
};

struct DvaeTrainConfig {
  std::string path;
  std::string name;
  std::string protocol;  // protocol config name or path
  DvaeOptions model;
  DvaeTrainOptions training;
  DvaeFinetuneOptions finetune;
  DvaeNoisePrior noise_prior;
  DenoiseOptions denoise;
  DvaeRefinerConfig refiner;
};

constexpr const char* kDvaeBundleFormat = "motionfork-dvae-1";

// A bundle's dvae.yaml.
struct DvaeManifest {
  std::string format = kDvaeBundleFormat;
  std::string protocol;
  double fps = 0;
  DvaeOptions model;
  SkeletonSpec skeleton;
  std::vector<double> mean,
      std;  // per value [J * 3]: normalisation (metres, window-mean-root relative)
  DvaeNoisePrior noise_prior;
  bool finetuned = false;  // the encoder was fine-tuned on noisy data (regression mode)
  std::vector<std::string> finetune_noise;  // the corruptions it was fine-tuned on
  RefinerOptions refiner;                   // the denoising refiner (channels 0: none)
  // Its output blended with the input by the local correction size (refiner_blend.h; fitted at
  // the end of `dvae refine`); no weights: the refiner's output as it is.
  RefinerBlend refiner_blend;
  DenoiseOptions denoise;  // defaults of `motionfork denoise`
  std::vector<std::pair<std::string, std::string>> info;
};

// Throws std::invalid_argument naming the field and the rule it broke.
void ValidateDvaeOptions(const DvaeOptions& o);

}  // namespace motionfork
