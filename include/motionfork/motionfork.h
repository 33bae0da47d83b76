// motionfork's public C++ API: load a trained model bundle, give it a history, get K diverse
// futures (optionally with some body parts shared by all of them), and check them against the
// bundle's angle-range constraints.
//
// It also repairs histories before forecasting (Imputer: missing joints filled by an HG-VAE;
// Denoiser: noise removed by a Motion-DVAE), scores poses under the bundle's pose prior, and
// writes what the `motionfork` command writes (prediction files, BVH). The command and this API
// run the same pipeline library (src/pipeline), so the same inputs give the same futures.
//
// Plain C++17 and std types only: no LibTorch, Eigen or YAML headers. Link `motionfork::api`
// (CMake: find_package(motionfork) after `cmake --install`; see README.md, "Use it from C++").
//
// Thread safety: a loaded Model is immutable; its const methods may be called from several threads
// at once (each call has its own working memory). Imputer and Denoiser run optimisers on their own
// state: call one object from one thread at a time (load one per thread to work in parallel).
// LoadOptions::threads changes process-wide thread pools: set it before starting threads.
//
// Conventions: positions are metres in the history's own world frame, stored row-major as
// [frames, joints, 3] (x, y, z per joint, joints in joint_names() order, root first); frame rates
// are Hz. Errors are exceptions: std::invalid_argument for arguments that break a documented
// rule ("expected N, got M"), std::runtime_error for missing or malformed files (the message
// names the file, the line or key, what was expected and what was found).
//
//   motionfork::Model model = motionfork::Model::Load("models/bandai");
//   std::vector<float> history = model.ReadMotion("walk.bvh");   // or your own [T, J, 3] floats
//   motionfork::Futures futures = model.Predict(history, {/*k=*/10, /*seed=*/0, {"legs"}});
//   for (const motionfork::SampleCheck& s : model.Check(futures)) { /* s.valid ... */ }
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "motionfork/version.h"

namespace motionfork {

// The library's version, "MAJOR.MINOR.PATCH" (MOTIONFORK_VERSION_STRING of the headers it was
// built with; compare to detect a header / library mismatch).
const char* Version();

// Call first thing in main(). OpenBLAS chooses its kernels from the CPU model when it loads and
// falls back to a slow generic one (about 5x slower) on CPUs newer than it knows; this re-executes
// the program with $OPENBLAS_CORETYPE set to the best kernel the CPU supports when that happened,
// and returns at once otherwise (or when the user set $OPENBLAS_CORETYPE). Optional: setting
// $OPENBLAS_CORETYPE yourself (e.g. SkylakeX, Haswell) has the same effect.
void UseFastBlasKernels(char** argv);

// How Model::Load finds what a bundle refers to.
struct LoadOptions {
  // Folder of the shipped configs (holding constraints/, skeletons/, ...). "" = the first that
  // exists of: $MOTIONFORK_CONFIG_DIR, the installed configs (<prefix>/share/motionfork/configs),
  // the source tree's configs/ (builds used in place).
  std::string config_dir;
  // Constraint set used by Check(): a shipped name ("bandai") or a YAML file path. "" = the
  // bundle's own (BUNDLE/constraints.yaml, the set it was trained with), else the shipped set
  // named like its protocol, if there is one. "none" = no set (Check() then throws).
  std::string constraints;
  // > 0: pin LibTorch's and OpenBLAS's thread pools to this many threads (process-wide; engines
  // sharing the CPU want 1 or 2). 0 = leave them as they are.
  int threads = 0;
  // How ReadMotion() and Conform() map a motion whose joint names are not the model's: "" = by
  // the rig convention (configs/rigs/: Mixamo, CMU, Unreal, SMPL, ...) that explains its names;
  // else a convention name or a joint map YAML (configs/rigs/README.md), always used.
  std::string joint_map;
  // How ReadMotion() and Conform() read a motion's frame; "" = told from the body (its size, the
  // pelvis-to-head axis, the knees), as the command does: unit "m", "cm", "mm" or "in"; up "y",
  // "z", "x", "-y", "-z" or "-x"; left_right "as-labelled" or "swapped".
  std::string unit, up, left_right;
  // The generator's products: "auto" (the default: bf16 where the CPU has AVX512-BF16, fp32
  // elsewhere), "fp32" (float32) or "bf16" (bfloat16 inputs and float32 sums, on CPUs with
  // AVX512-BF16; elsewhere Load throws). bf16's futures are within 1 mm of fp32's, a quarter of a
  // millimetre apart on average (RESULTS.md "bf16 products").
  std::string precision = "auto";
};

// One body part the model samples with its own latent code.
struct Part {
  std::string name;                 // e.g. "legs"
  std::vector<std::string> joints;  // joints whose motion this part predicts (never the root)
};

// What Model::Predict should produce.
struct PredictOptions {
  int k = 50;         // futures to sample (>= 1)
  uint64_t seed = 0;  // same model, history, options and seed: the same futures, bit for bit
  // Parts (names from Model::parts()) whose latent code all k futures share. The first part in
  // prediction order sees only the history, so fixing it makes its joints identical in every
  // future; a later part also depends on the parts before it, so its joints are identical only
  // when those are fixed too.
  std::vector<std::string> fixed_parts;
  // When the bundle carries constraints.yaml: predicted poses that break its angle ranges (or its
  // rigid groups, e.g. the pelvis) are moved back, as little as it takes; false keeps the raw
  // network output. Fixed parts stay identical across futures either way.
  bool repair = true;
};

// K futures of one history.
//
// Layout: sample i is the history followed by future i, as in the prediction files the command
// writes (OUT.npy [k, history_frames + frames, joints, 3]); here the shared history frames are
// stored once (`history`) and the futures apart (`positions`); Sequence(i) joins them.
struct Futures {
  int k = 0;               // samples
  int frames = 0;          // frames per future (Model::future_frames())
  int joints = 0;          // joints per frame (Model::joint_names().size())
  double fps = 0;          // Hz
  int history_frames = 0;  // frames of `history` (Model::history_frames())
  // [k, frames, joints, 3] metres, in the history's world frame. A model with a trajectory
  // network (its bundle's trajectory/) moves each future's root (root_moves); otherwise it
  // predicts poses relative to the root and keeps the root where the history ended.
  std::vector<float> positions;
  bool root_moves = false;
  // [history_frames, joints, 3] metres: the history frames the futures continue (after any
  // repair), in the same frame.
  std::vector<float> history;

  // Future i as [frames, joints, 3]; i in [0, k).
  const float* sample(int i) const {
    return positions.data() + static_cast<size_t>(i) * frames * joints * 3;
  }
  // Sample i as the prediction file holds it: [history_frames + frames, joints, 3].
  std::vector<float> Sequence(int i) const;
};

// How Model::ExportBvh writes a BVH file.
struct BvhExportOptions {
  int sample = -1;  // the sample to write; -1 = every sample, OUT_00.bvh, OUT_01.bvh, ...
  bool exact_lengths = false;  // false: each bone at its mean length; true: per-frame lengths
  double scale = 0.01;         // metres per BVH unit (0.01: the file is in centimetres)
  std::string rotation_order = "ZXY";  // rotation channels' axis order, a permutation of XYZ
};

// Check of one motion (e.g. one future): angle ranges frame by frame, and the pose prior.
struct SampleCheck {
  // Every angle of every frame is defined and inside its range, and the mean prior NLL is within
  // the prior's bound (when the bundle has a prior).
  bool valid = true;
  // Frames (0 = the first frame checked) where some angle is outside its range.
  std::vector<int> violating_frames;
  // Frames where some angle is undefined (a zero-length bone, or two collinear bones spanning a
  // plane); such frames are not valid either.
  std::vector<int> undefined_frames;
  // Names of the constraints violated in some frame, in the set's order (e.g. "Leg2ThighPlane_L").
  std::vector<std::string> violated_constraints;
  // The bundle's pose prior (has_prior()): the mean negative log-likelihood per pose, nats (NaN
  // without a prior), and whether it lies within the prior's bound (prior_bound()); a sample
  // above it is not valid either.
  double prior_nll = std::numeric_limits<double>::quiet_NaN();
  bool prior_ok = true;
  // The tests it fails, in this order: "angle_ranges" (violating or undefined frames),
  // "prior_nll"; empty when valid.
  std::vector<std::string> failed;
};

// What CheckHistory() finds before forecasting: the HG-VAE window score of the history against
// its out-of-distribution bound (NaN when the bundle has no HG-VAE, BUNDLE/hgvae) and the doubts,
// for people ("scale: ...", "axis: ...", "left/right: ...", "joint Hand_L: ...", "angle ranges:
// ...", "prior: ...", "HG-VAE: ..."). Futures of a doubted history are not to be trusted.
struct HistoryDoubts {
  double window_score = std::numeric_limits<double>::quiet_NaN();
  double window_bound = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> doubts;  // empty: the history looks like what the model knows
};

// A trained forecasting model: a bundle folder (model.yaml + generator.pt, as written by
// `motionfork train`) with its skeleton, body parts and constraint set. Immutable after Load;
// move-only.
class Model {
 public:
  // Loads the bundle in `bundle_dir` and binds its constraint set (see LoadOptions). Throws
  // std::runtime_error naming the missing or malformed file (model.yaml, generator.pt, the
  // constraint config), std::invalid_argument for bad options.
  static Model Load(const std::string& bundle_dir, const LoadOptions& options = {});

  ~Model();
  Model(Model&&) noexcept;
  Model& operator=(Model&&) noexcept;

  // The model's skeleton: joint names (root first) and each joint's parent index (-1 for the
  // root); the layout of every [frames, joints, 3] array this API takes or returns.
  const std::vector<std::string>& joint_names() const;
  const std::vector<int>& parents() const;
  // Left/right joint pairs as (left, right) indices, e.g. for colouring sides.
  const std::vector<std::pair<int, int>>& left_right_pairs() const;
  // Body parts in prediction order (the bundle's partition); their names are what
  // PredictOptions::fixed_parts takes.
  const std::vector<Part>& parts() const;
  // History frames Predict() uses and future frames it returns, at fps() Hz.
  int history_frames() const;
  int future_frames() const;
  double fps() const;
  // The protocol the model was trained under (e.g. "bandai").
  const std::string& protocol() const;
  // The constraint set Check() uses: its name and YAML file; both "" when the model has none.
  const std::string& constraint_set() const;
  const std::string& constraint_file() const;
  // The configs folder Load() used ("" when none was found).
  const std::string& config_dir() const;

  // Samples options.k futures of a history. history: [T, J, 3] metres at fps() Hz, J =
  // joint_names().size(), T >= history_frames(); the last history_frames() frames are used.
  // Throws std::invalid_argument when the size is not a whole number of frames, there are too
  // few frames, a value is NaN/Inf (naming the frame and joint), k outside 1..10000, or a fixed
  // part is unknown (listing the known parts).
  Futures Predict(const std::vector<float>& history, const PredictOptions& options = {}) const;

  // Checks every future against the constraint set and the bundle's prior (when it has one): one
  // SampleCheck per sample, frames counted from the first future frame. Throws std::logic_error
  // when the model has no constraint set, std::invalid_argument when futures do not match the
  // model's joints.
  std::vector<SampleCheck> Check(const Futures& futures) const;
  // The same for any motion on the model's joints (e.g. the history): [T, J, 3] metres.
  SampleCheck CheckMotion(const std::vector<float>& positions) const;
  // The plausibility gate `motionfork predict` runs: the last history_frames() frames of
  // `history` ([T, J, 3] metres, the model's joints and frame, as Predict() takes it) scored by
  // the bundle's HG-VAE, prior and angle ranges, its body measured (size, up axis, left/right,
  // bones). Throws std::invalid_argument like Predict() for a bad history.
  HistoryDoubts CheckHistory(const std::vector<float>& history) const;

  // Reads a motion file (.bvh in centimetres, .npy [T, J, 3] metres in joint_names() order, .csv
  // as written by `motionfork convert`), keeps the model's joints (by name; a Bandai BVH's 22
  // joints -> the model's 17) and resamples it to fps(). Returns [T, J, 3] metres, ready for
  // Predict(). Another rig's joints (Mixamo, SMPL, ...) are mapped by their roles
  // (LoadOptions::joint_map); `notes`, when given, receives how, for people. Throws
  // std::runtime_error naming the file and what is wrong in it, std::invalid_argument when its
  // joints do not map onto the model's.
  std::vector<float> ReadMotion(const std::string& path,
                                std::vector<std::string>* notes = nullptr) const;
  // The same for a motion already read (motionfork::ReadMotion): its joints mapped onto the
  // model's, resampled to fps(). Throws std::invalid_argument when its joints do not map onto
  // the model's or a value the model needs is NaN/Inf (naming the frame and joint).
  std::vector<float> Conform(const struct MotionData& motion,
                             std::vector<std::string>* notes = nullptr) const;

  // True when the bundle carries a pose prior (BUNDLE/prior/).
  bool has_prior() const;
  // The prior's negative log-likelihood of each frame's pose, nats (lower = more plausible):
  // positions [T, J, 3] metres on the model's joints. Throws std::logic_error without a prior.
  std::vector<double> PriorNll(const std::vector<float>& positions) const;
  // Their mean over the frames: the figure `motionfork check` and the prediction file report.
  double MeanPriorNll(const std::vector<float>& positions) const;
  // The bound on a sample's mean prior NLL for it to be valid: the 99th percentile of the NLL of
  // real held-out poses (the prior's training summary); NaN without a prior or that figure.
  double prior_bound() const;

  // Writes futures as `motionfork predict -o OUT` does: OUT.npy [k, history_frames + frames, J, 3]
  // and OUT.json (skeleton, parts, each future's validity under the bundle's own constraints and
  // prior), readable by `motionfork render` and `motionfork export`. `options` are those the
  // futures were predicted with (recorded in OUT.json). Each file is written all-or-nothing.
  // Returns OUT (the path without extension).
  std::string WritePrediction(const std::string& out, const Futures& futures,
                              const PredictOptions& options = {}) const;

  // Writes samples (history + future) as BVH files of joint rotations on a rest pose, as
  // `motionfork export` does; `out` ends in .bvh. Returns the paths written.
  std::vector<std::string> ExportBvh(const std::string& out, const Futures& futures,
                                     const BvhExportOptions& options = {}) const;

 private:
  struct Impl;
  explicit Model(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// A motion with its missing values filled.
struct Imputed {
  std::vector<float> positions;  // [T, J, 3] metres; observed values exactly as given
  int missing_values = 0;        // values that were NaN
};

// An HG-VAE bundle (hgvae.yaml + hgvae.pt, e.g. models/bandai/hgvae): fills missing joints of a
// motion from the frames around them.
class Imputer {
 public:
  // Throws std::runtime_error naming the missing or malformed file.
  static Imputer Load(const std::string& bundle_dir);
  ~Imputer();
  Imputer(Imputer&&) noexcept;
  Imputer& operator=(Imputer&&) noexcept;

  const std::vector<std::string>& joint_names() const;  // the layout of positions, root first
  double fps() const;                                   // Hz
  int window_frames() const;  // the motion must have at least this many frames

  // positions: [T, J, 3] metres at fps() on joint_names(); NaN marks a missing value (the root
  // must be observed). Returns the motion with every NaN filled. Throws std::invalid_argument for
  // a wrong size, too few frames, a missing root value or a window with nothing observed.
  Imputed Impute(const std::vector<float>& positions) const;

 private:
  struct Impl;
  explicit Imputer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// A Motion-DVAE bundle (dvae.yaml + dvae.pt, e.g. models/bandai/dvae): removes noise from
// estimated joint positions, in its bundle's mode (regression or optimisation).
class Denoiser {
 public:
  static Denoiser Load(const std::string& bundle_dir);
  ~Denoiser();
  Denoiser(Denoiser&&) noexcept;
  Denoiser& operator=(Denoiser&&) noexcept;

  const std::vector<std::string>& joint_names() const;
  double fps() const;

  // positions: [T, J, 3] metres at fps() on joint_names(), T >= 2, every value finite. Returns
  // the denoised motion, same shape; the same input gives the same output.
  std::vector<float> Denoise(const std::vector<float>& positions) const;
  // The same in another mode: "refiner", "regression" or "optimisation" ("" = the bundle's).
  // Throws std::invalid_argument naming the modes for any other, or when the bundle lacks the
  // refiner that mode needs.
  std::vector<float> Denoise(const std::vector<float>& positions, const std::string& mode) const;

 private:
  struct Impl;
  explicit Denoiser(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// A motion with its skeleton, as motion files hold it.
struct MotionData {
  // [frames, joints, 3] metres; NaN where the file marks a value missing (NaN in .npy, an empty
  // or nan field in .csv).
  std::vector<float> positions;
  std::vector<std::string> joint_names;  // root first; .npy files store none: "joint_0", ...
  std::vector<int> parents;              // each joint's parent index, -1 for the root
  double fps = 0;                        // Hz
  int frames() const;                    // positions.size() / (3 x joints)
};

// How ReadMotion reads a file (the commands' --skeleton, --fps, --bvh-scale).
struct FileReadOptions {
  // A skeleton config name (e.g. "bandai") or YAML path: the motion is put on that skeleton (its
  // joints selected and ordered by name, or by position for .npy). "" = as the file stores it.
  std::string skeleton;
  double fps = 0;           // Hz, for files that store none (.npy); 0 = 30 Hz for those
  double bvh_scale = 0.01;  // BVH length unit in metres (0.01: centimetres)
  std::string config_dir;   // where `skeleton` is looked up; "" as LoadOptions::config_dir
};

// Reads a .bvh, .npy or .csv motion file. Throws std::runtime_error naming the file and what is
// wrong in it, std::invalid_argument for bad options or a skeleton the file does not fit.
MotionData ReadMotion(const std::string& path, const FileReadOptions& options = {});

// How WriteMotion writes a file (BVH only; .npy and .csv store positions as they are).
struct FileWriteOptions {
  double bvh_scale = 0.01;             // metres per BVH unit (0.01: the file is in centimetres)
  std::string rotation_order = "ZXY";  // rotation channels' axis order, a permutation of XYZ
};

// Writes a motion as .bvh (joint rotations fitted to the positions; needs parents), .npy
// [T, J, 3] or .csv (with the joint names and fps), chosen by the extension; all-or-nothing.
// Throws std::invalid_argument for a motion whose sizes disagree or holds NaN/Inf (naming the
// frame and joint), std::runtime_error when the file cannot be written.
void WriteMotion(const std::string& path, const MotionData& motion,
                 const FileWriteOptions& options = {});

// A pose prior bundle (a folder written by `motionfork prior train`, e.g. models/bandai/prior):
// how plausible each pose is.
class Prior {
 public:
  // Throws std::runtime_error naming the missing or malformed file.
  static Prior Load(const std::string& bundle_dir);
  ~Prior();
  Prior(Prior&&) noexcept;
  Prior& operator=(Prior&&) noexcept;

  const std::vector<std::string>& joint_names() const;  // the layout of positions, root first

  // Negative log-likelihood of each frame's pose, nats (lower = more plausible): positions
  // [T, J, 3] metres on joint_names(), every value finite. Throws std::invalid_argument otherwise.
  std::vector<double> Nll(const std::vector<float>& positions) const;

 private:
  struct Impl;
  explicit Prior(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace motionfork
