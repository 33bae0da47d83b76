// A prediction on disk: what `motionfork predict -o OUT` writes and `render` / `export` read.
//
//   OUT.npy   float32 [K, T, J, 3], metres: every sample is the history (t_his frames) followed by
//             its future (t_pred frames), T = t_his + t_pred.
//   OUT.json  the description: model, protocol, history file, start frame, K, seed, fps, t_his,
//             t_pred, the skeleton (joint names, parent indices, left/right pairs, body parts in
//             prediction order), the fixed parts, whether the futures' root moves (root_moves:
//             the array holds world positions either way), the array's file name and shape, and one
//             entry per sample with its validity: valid, the judges it fails ("failed":
//             angle_ranges, prior_nll, history), its violating frames and mean prior NLL when the
//             bundle has them; the prior's bound (prior_nll_bound) and what was checked of the
//             history (history_validity, history_check: the HG-VAE window score and the doubts).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

// Per-sample plausibility figures over the sample's future frames.
struct SampleValidity {
  // Passes every judge that is on: no angle range violated, the mean prior NLL within the prior's
  // bound, and (futures) a history without doubts.
  bool valid = true;
  int violating_frames = 0;         // future frames with at least one violation
  std::optional<double> prior_nll;  // mean over future frames of the pose prior's NLL
  bool prior_ok = true;             // prior_nll <= the prior's bound (true when either is unknown)
  bool history_ok = true;           // the history it continues raised no doubt (HistoryCheck)
  // The judges it fails, in this order: "angle_ranges", "prior_nll", "history"; empty when valid.
  std::vector<std::string> Failed() const;
};

// What the history was found to be before forecasting (pipeline/history_check.h): its HG-VAE
// window score against the bundle's out-of-distribution bound, and every doubt, for people
// ("scale: ...", "axis: ...", "angle ranges: ...").
struct HistoryCheck {
  std::optional<double> window_score;  // the HG-VAE's posterior score (higher = more typical)
  std::optional<double> window_bound;  // below it, a window is out of distribution
  std::vector<std::string> doubts;     // empty: the history looks like what the model knows
};

// When the history had missing values filled by an HG-VAE (predict --impute).
struct HistoryImputation {
  std::string model;        // HG-VAE bundle
  int missing_values = 0;   // in the history frames
  double score_before = 0;  // posterior score with the missing values at the training mean
  double score_after = 0;   // imputed
  // For reports, not written to OUT.json: the score's name and the training windows' mean and
  // standard deviation of it.
  std::string score_kind;
  double training_mean = 0, training_std = 0;
};

struct HistoryDenoising {
  std::string model;       // Motion-DVAE bundle
  std::string mode;        // regression | optimisation
  int frames = 0;          // frames denoised: the history and up to one window before it
  double mean_change = 0;  // mean distance moved per history joint, metres
  int first_frame = 0;     // first frame denoised (for reports, not written to OUT.json)
};

// How the history file was read onto the model (predict's reading flags, "" = detected), so that
// `export` can write the futures back on the file's own rig the same way.
struct HistoryReading {
  std::string path;  // the history file, absolute (export finds it from any folder)
  std::string skeleton, joint_map, unit, up, left_right;
  double bvh_scale = 0;  // 0 = BVH read as centimetres, the unit then told from the body
  double fps = 0;        // for files that store no rate
};

struct Prediction {
  std::string model, protocol, history;
  int start_frame = 0, k = 0, t_his = 0, t_pred = 0;
  uint64_t seed = 0;
  double fps = 0;
  std::shared_ptr<const Skeleton> skeleton;  // names, parents, left/right pairs, parts ("default")
  std::vector<std::string> fixed_parts;
  // World positions either way; true: each future's root moves as the model's trajectory says
  // (a bundle with trajectory/), false: it stays at the last history frame's root.
  bool root_moves = false;
  std::vector<float> positions;         // [K, t_his + t_pred, J, 3]
  std::vector<SampleValidity> samples;  // K entries, or empty when validity was not computed
  std::optional<SampleValidity> history_validity;  // the same figures for the history frames
  std::optional<double> prior_bound;          // the prior's bound on a mean NLL (its held-out q99)
  std::optional<HistoryCheck> history_check;  // doubts about the history, when checked
  std::optional<HistoryReading> reading;      // how the history file was read, when known
  std::optional<HistoryImputation> imputation;  // the history's missing values were imputed
  std::optional<HistoryDenoising> denoising;    // the history was denoised (after any imputation)

  int frames() const { return t_his + t_pred; }
  int joints() const { return skeleton ? skeleton->num_joints() : 0; }
  // Sample k as a flat [T, J, 3] slice.
  const float* sample(int k) const {
    return positions.data() + static_cast<size_t>(k) * frames() * joints() * 3;
  }
};

// Writes OUT.json and OUT.npy (OUT given with or without ".npy"/".json"); all-or-nothing per file.
// Returns the base path (without extension).
std::string WritePrediction(const std::string& out, const Prediction& p);

// Reads a prediction from its .json or .npy path (the other file is found beside it). Throws
// FormatError naming the file and the key or shape that is wrong.
Prediction ReadPrediction(const std::string& path);

// Whether `path` names a prediction: its .json, or a .npy with the .json of the same name beside it
// (a lone .npy is a motion).
bool IsPredictionPath(const std::string& path);

}  // namespace motionfork
