// motionfork's public C++ API: load a trained model bundle, give it a history, get K diverse
// futures (optionally with some body parts shared by all of them), and check them against the
// bundle's angle-range constraints.
//
// Plain C++17 and std types only: no LibTorch, Eigen or YAML headers. Link `motionfork::api`
// (CMake: find_package(motionfork) after `cmake --install`; see README.md, "Use it from C++").
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
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace motionfork {

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
struct Futures {
  int k = 0;       // samples
  int frames = 0;  // frames per future (Model::future_frames())
  int joints = 0;  // joints per frame (Model::joint_names().size())
  double fps = 0;  // Hz
  // [k, frames, joints, 3] metres, in the history's world frame. The model predicts poses
  // relative to the root and keeps the root where the history ended.
  std::vector<float> positions;

  // Sample i as [frames, joints, 3]; i in [0, k).
  const float* sample(int i) const {
    return positions.data() + static_cast<size_t>(i) * frames * joints * 3;
  }
};

// Angle-range check of one motion (e.g. one future), frame by frame.
struct SampleCheck {
  // Every angle of every frame is defined and inside its range.
  bool valid = true;
  // Frames (0 = the first frame checked) where some angle is outside its range.
  std::vector<int> violating_frames;
  // Frames where some angle is undefined (a zero-length bone, or two collinear bones spanning a
  // plane); such frames are not valid either.
  std::vector<int> undefined_frames;
  // Names of the constraints violated in some frame, in the set's order (e.g. "Leg2ThighPlane_L").
  std::vector<std::string> violated_constraints;
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
  // few frames, a value is NaN/Inf (naming the frame and joint), k < 1, or a fixed part is
  // unknown (listing the known parts).
  Futures Predict(const std::vector<float>& history, const PredictOptions& options = {}) const;

  // Checks every future against the constraint set: one SampleCheck per sample, frames counted
  // from the first future frame. Throws std::logic_error when the model has no constraint set,
  // std::invalid_argument when futures do not match the model's joints.
  std::vector<SampleCheck> Check(const Futures& futures) const;
  // The same for any motion on the model's joints (e.g. the history): [T, J, 3] metres.
  SampleCheck CheckMotion(const std::vector<float>& positions) const;

  // Reads a motion file (.bvh in centimetres, .npy [T, J, 3] metres in joint_names() order, .csv
  // as written by `motionfork convert`), keeps the model's joints (by name; a Bandai BVH's 22
  // joints -> the model's 17) and resamples it to fps(). Returns [T, J, 3] metres, ready for
  // Predict(). Throws std::runtime_error naming the file and what is wrong in it,
  // std::invalid_argument when its joints do not include the model's.
  std::vector<float> ReadMotion(const std::string& path) const;

 private:
  struct Impl;
  explicit Model(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace motionfork
