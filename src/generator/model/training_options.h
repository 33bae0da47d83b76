// Generator training settings (configs/models/*.yaml, sections `generator`, `losses`,
// `multimodal` and `training`). Plain structs, no YAML: bundle/generator_bundle.h reads them. They
// sit with the model, not in generator/training, because the bundle layer reads them and the
// training target links the bundle layer (it writes bundles), as imputation/hgvae_options.h does.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "generator/kernels/precision.h"
#include "generator/model/generator_options.h"

namespace motionfork {

struct LossWeights {
  double past_reconstruction = 100;     // squared error of the reconstructed history
  double limb_length = 500;             // predicted bone lengths vs the history's last frame
  std::vector<double> diversity;        // per part; GSPS H36M: 8, 25
  std::vector<double> diversity_scale;  // per part: alpha in exp(-d / alpha); GSPS H36M: 100, 300
  double best_of_many = 2;              // min over samples of the future's squared error
  double multimodal = 1;                // the same against pseudo multimodal futures
  double prior_nll = 0.01;              // flow-prior NLL of predicted poses (needs a prior)
  double angle = 100;                   // angle-range penalty (needs constraints)
};

struct MultimodalOptions {
  double last_pose_threshold = 0.05;  // mean per-joint distance (m) between last history poses
  double future_min_distance = 0.1;   // mean per-joint distance (m) the futures must differ by
  int max_per_window = 10;
  // For a generator in the body's frame: match (and retarget) the windows in each one's own body
  // frame; false: in the data's axes, as GSPS, each pseudo future then turned with its window.
  bool body_frame = false;
};

// Training windows varied at random (config section `augmentation`; issue 28: forecasts that
// generalise to styles never seen). Every key is off by default: a config without the section
// trains as before, draw for draw. A varied window's pseudo multimodal futures are varied with it.
struct AugmentationOptions {
  // Share of windows mirrored: left and right joints exchanged and the axis the windows' hip lines
  // lie along reflected (generator/training/augmentation.h's MakeMirrorPlan: headings kept in
  // the body's frame; in the data's axes for windows facing the data's usual way).
  double mirror = 0;
  // Body size: each window's poses times a factor drawn log-uniformly in [1 / scale, scale].
  double scale = 1;
  // Playback speed: a factor drawn log-uniformly in [1 / speed, speed]; the window's frames are
  // read that much faster about its last history frame (interpolated; where the clip, or a pseudo
  // window's, is too short for the drawn factor, the largest that fits them all).
  double speed = 1;
  // Metres: Gaussian noise (standard deviation) on the history the network reads; the losses see
  // the clean history (a forecaster that tolerates repaired, e.g. imputed, histories).
  double history_noise = 0;

  bool enabled() const { return mirror > 0 || scale > 1 || speed > 1 || history_noise > 0; }
};

struct TrainingOptions {
  std::vector<int64_t> samples_per_part;  // nested samples per part (GSPS: 10, 10)
  int batch_histories = 16;
  int epochs = 500;
  int windows_per_epoch = 5000;
  int lr_constant_epochs = 100;  // then linear decay to 0 at `epochs`
  double learning_rate = 1e-3;
  double grad_clip = 100;
  int window_stride = 5;     // training windows: every 5th start in every clip
  int prior_frame_step = 3;  // prior NLL on every 3rd predicted frame (random offset)
  uint64_t seed = 0;
  int threads = 1;
  // Several workers: batch statistics over every worker's share (one sum over the workers per
  // batch-normalised layer, forward and backward), so that the run takes one worker's steps;
  // false: each worker normalises its own share (PyTorch DDP's default, no extra traffic).
  bool sync_batch_norm = true;
  // The residual blocks' products, forward and backward (issue 30): fp32; bf16 (bfloat16 inputs,
  // float32 sums, needs AVX512-BF16); auto (bf16 where the CPU has it). `train --precision`
  // replaces it for one run.
  Precision precision = Precision::kFp32;
};

// The trajectory network's training (configs/models/*.yaml, section `trajectory`; issue 27): after
// the generator, on the same training windows in the body's frame, their true poses in, their
// root's motion out.
struct TrajectoryTrainOptions {
  int n_in = 0;  // DCT coefficients of the poses; 0: the generator's n_pre
  int n_out = 10;
  int hidden = 512;
  int layers = 3;
  int epochs = 30;
  int lr_constant_epochs = 15;  // then linear decay to 0 at `epochs`
  int batch = 256;              // windows a step
  int window_stride = 5;        // every 5th start in every clip
  double learning_rate = 1e-3;
  // Every n-th training clip (n - 1, 2n - 1, ...) is held out and picks the epoch kept (the one
  // with the lowest final root error there); 0: none held out, the last epoch kept.
  int validation_every = 10;
  double final_weight = 1;       // the last frame's root distance, beside the mean over frames
  double skating_weight = 1;     // feet on the ground that slide (needs the ankles: rig roles)
  double contact_height = 0.05;  // metres above the window's lowest ankle that count as contact
  uint64_t seed = 0;
};

struct GeneratorTrainConfig {
  std::string path;
  std::string name;
  std::string protocol;        // protocol config name or path
  std::string prior;           // prior bundle folder ("" = no prior loss)
  std::string constraints;     // constraints config name or path ("" = no angle loss)
  GeneratorOptions generator;  // t_his, t_pred, num_nodes come from the protocol
  // generator.body_frame: true: the network learns in the body's frame about the protocol's up
  // axis (GeneratorOptions::body_frame).
  bool body_frame = false;
  LossWeights losses;
  MultimodalOptions multimodal;
  TrainingOptions training;
  AugmentationOptions augmentation;
  std::optional<TrajectoryTrainOptions> trajectory;  // needs body_frame
};

}  // namespace motionfork
