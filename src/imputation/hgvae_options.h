// HG-VAE settings (configs/models/hgvae_*.yaml; bundles' hgvae.yaml). Plain structs, no LibTorch.
//
// Sizes follow the HG-VAE paper (../shared/seeds/hgvae-paper.txt) scaled to our skeletons: one
// graph node per coordinate (joints x 3), DCT coefficients of the window as node features, and
// stochastic levels from one global node down to the full graph.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "imputation/fill_smoothing.h"
#include "refine/refiner_options.h"

namespace motionfork {

// One stochastic level: its latent graph (nodes x features).
struct HgvaeLevel {
  int nodes = 0;     // 0 = every coordinate of the pose (the full graph, e.g. 48 for 16 joints)
  int features = 0;  // latent features per node
};

struct HgvaeOptions {
  // Top (one global node) to bottom (the full graph). Paper: 1x256, 8x128, 24x128, 54x128.
  std::vector<HgvaeLevel> levels = {{1, 256}, {8, 128}, {24, 128}, {0, 128}};
  int width = 256;            // features of the decoder's deterministic path (paper: 256)
  int encoder_blocks = 1;     // residual graph-conv blocks (GCB) per level, bottom-up pass
  int decoder_blocks = 1;     // GCBs per level, top-down pass
  int stochastic_levels = 0;  // 0 = all; d > 0: only the top d levels sample, the others take
                              // their prior mean and add no KL (the paper's stochastic depth)
  int window = 0;             // frames per window; 0 = the protocol's history length (t_his)
  // p(x | z) = N(mean, var): false = one learned log-variance per coordinate and frame (shared by
  // all windows, so every value must be explained); true = the decoder predicts it per window
  // (better likelihoods, but it may give up on hard values by widening them).
  bool predicted_variance = false;
  double label_dropout = 0.25;  // conditional models: share of training windows whose one-hot is
                                // all zero, so the model also works without a class
};

struct HgvaeTrainOptions {
  int epochs = 60;
  int windows_per_epoch = 20000;  // random training windows per epoch
  int batch_size = 256;           // windows per Adam step (paper: 800)
  double learning_rate = 1e-3;    // Adam (paper: 1e-3), constant
  double grad_clip = 100;         // gradient-norm clip (paper: 100)
  int kl_warmup_epochs = 20;      // KL weight rises linearly from kl_start to 1 over these epochs
  double kl_start = 1e-3;         // (paper: 0.001 -> 1 over 200 of 5000 epochs)
  std::string condition;          // "" = unconditional; "action" = one-hot of the clip's action
  double held_out_share = 0.05;   // training clips held out: per-epoch ELBO and the OoD statistics
  int held_out_windows = 2000;    // at most this many held-out windows (stride 1 over the clips)
  uint64_t seed = 0;
  int threads = 1;
};

enum class ImputeObjective {
  kPosterior,  // the paper's: sum over levels of log p(mu_q,l | z<l), the posterior means under the
               // prior
  kJoint,      // the same plus log p(x | z = posterior means): also asks the decoder to explain x
};
// Their names in configs, bundles and flags.
inline constexpr EnumName<ImputeObjective> kImputeObjectiveNames[] = {
    {ImputeObjective::kPosterior, "posterior"}, {ImputeObjective::kJoint, "joint"}};
const char* ToString(ImputeObjective objective);
ImputeObjective ParseImputeObjective(const std::string& text);  // "posterior" | "joint"

// Where the missing values of a whole motion start before the Adam steps (ImputeMotion).
enum class ImputeStart {
  kMean,     // the training mean pose (the paper's)
  kLinear,   // linear interpolation in time from the observed frames (interpolation_fill.h)
  kSpline,   // natural cubic-spline interpolation in time
  kRefiner,  // the bundle's refiner over the spline, linear and rigid-limb fills (refine/)
};
inline constexpr EnumName<ImputeStart> kImputeStartNames[] = {{ImputeStart::kMean, "mean"},
                                                              {ImputeStart::kLinear, "linear"},
                                                              {ImputeStart::kSpline, "spline"},
                                                              {ImputeStart::kRefiner, "refiner"}};
const char* ToString(ImputeStart start);
// "mean" | "linear" | "spline" | "refiner"
ImputeStart ParseImputeStart(const std::string& text);

struct ImputeOptions {
  int steps = 10;              // Adam steps on the missing values (paper: 10, or 100)
  double learning_rate = 0.1;  // Adam step on normalised coordinates (one unit = one training std)
  ImputeObjective objective = ImputeObjective::kJoint;
  ImputeStart start = ImputeStart::kMean;
};

// Command-line overrides of a bundle's ImputeOptions; unset fields (steps < 0, learning_rate <= 0,
// objective "", start "") keep the bundle's value.
struct ImputeOverrides {
  int steps = -1;
  double learning_rate = 0;
  std::string objective;  // "posterior" | "joint" | ""
  std::string start;      // "mean" | "linear" | "spline" | ""
  ImputeOptions Apply(ImputeOptions o) const;
};

// Training the imputation refiner (`hgvae refine`): clean training windows with random masks
// (random values, gaps of one joint, a limb or a body part, up to the whole window), their spline,
// linear and rigid-limb fills in, the clean window the target at the missing values.
struct HgvaeRefinerConfig {
  RefinerOptions model = {96, 96, 24, {1, 2, 4, 8, 16, 1, 2, 4, 8, 16}, 7, false};
  RefinerTrainOptions training = {20, 6400, 32, 1e-3, 0.93, 10, 6, 5, 1};
};

struct HgvaeTrainConfig {
  std::string path;
  std::string name;
  std::string protocol;  // protocol config name or path
  HgvaeOptions model;
  HgvaeTrainOptions training;
  ImputeOptions impute;
  double ood_k = 2.0;  // a window is out of distribution when its score < mean - k * std
  // The out-of-distribution score: kJoint (posterior score + log p(x | posterior means)) by
  // default; kPosterior is the paper's, which on Bandai ranks mean-filled windows as more typical.
  ImputeObjective ood_score = ImputeObjective::kJoint;
  HgvaeRefinerConfig refiner;
};

}  // namespace motionfork

#include <memory>

#include "core/skeleton.h"
#include "imputation/window_gaussian.h"

namespace motionfork {

constexpr const char* kHgvaeBundleFormat = "motionfork-hgvae-1";

// A bundle's hgvae.yaml: everything needed to rebuild and use the model.
struct HgvaeManifest {
  std::string format = kHgvaeBundleFormat;
  std::string protocol;
  double fps = 0;                    // Hz
  HgvaeOptions model;                // levels with nodes resolved (no 0), window resolved
  SkeletonSpec skeleton;             // the protocol skeleton (root first; the root is dropped)
  std::vector<std::string> classes;  // one-hot order; empty = unconditional model
  std::vector<double> mean, std;     // per coordinate [N]: normalisation, metres (root-relative)
  ImputeObjective ood_score = ImputeObjective::kPosterior;  // what score_mean/std describe
  double score_mean = 0, score_std = 0;  // that score on held-out training windows
  double ood_k = 2.0;
  ImputeOptions impute;    // defaults for `motionfork impute`
  RefinerOptions refiner;  // the imputation refiner (channels 0: none; refine/refiner_options.h)
  // The refiner's correction per bucket of missing values (refiner_fills.h, kRefinerGapBuckets;
  // fitted on held-out clips by `motionfork hgvae calibrate`); empty: 1 everywhere.
  std::vector<double> refiner_weights;
  // How much of the local polynomial's departure from the spline to add per bucket (empty: none),
  // and whether to keep the rigid bones at their observed lengths (ImputationBlend).
  std::vector<double> refiner_local_weights;
  bool refiner_keep_bones = false;
  // > 0: those weights are adapted to each motion by probes of its own observed values, pulled
  // towards them as if by this many values (refiner_adaptation.h); 0: used as they are. One value
  // for every bucket or one per gap length class (ImputationBlend::adapt_values); empty: none.
  std::vector<double> refiner_adapt_values;
  // The filled values pulled towards a smooth path last (fill_smoothing.h); zeros: not at all.
  FillSmoothing refiner_smoothing;
  // Then the scope's missing values (the ones observed on one side only; or those and every value
  // of a motion no longer than the window): their conditional mean under a Gaussian over windows of
  // frames (window_gaussian.h; fitted by `motionfork hgvae fit-gaussian`), stored in the bundle as
  // `file`; no file: not at all.
  struct GaussianStage {
    std::string file;  // inside the bundle folder
    int frames = 0, coords = 0;
    long long windows = 0;
    GaussianScope scope = GaussianScope::kOneSided;
    std::shared_ptr<const WindowGaussian> model;  // loaded with the bundle
    bool enabled() const { return !file.empty(); }
  } refiner_gaussian;
  std::vector<std::pair<std::string, std::string>> info;  // provenance
};

// The widest level or block (features, width) a bundle may declare (ValidateHgvaeOptions); also
// at most 16 levels, 100 blocks each way and windows of 4096 frames.
constexpr int kMaxHgvaeWidth = 4096;

// Throws std::invalid_argument naming the field and the rule it broke. num_coords: nodes of the
// full graph (0 = not known yet: levels may still say 0).
void ValidateHgvaeOptions(const HgvaeOptions& o, int num_coords);
// Levels with 0 nodes -> num_coords, window 0 -> t_his; validated.
HgvaeOptions ResolveHgvaeOptions(HgvaeOptions o, int num_coords, int t_his);

}  // namespace motionfork
