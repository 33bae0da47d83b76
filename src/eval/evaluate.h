// The evaluation job: a predictor over a protocol's test windows -> the protocol's figures, overall
// and per action, with the time spent in the predictor and in the metrics.
//
// Plausibility figures (angle-violation rate, prior NLL) come from other modules (constraints,
// flow prior): they plug in as FrameScorers, so this module depends on neither.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "eval/metrics.h"
#include "eval/predictor.h"
#include "eval/root_motion.h"
#include "eval/test_set.h"

namespace motionfork {

// One plausibility figure, computed per frame and averaged over frames.
struct FrameScorer {
  std::string name;  // figure name and JSON key, e.g. "angle_violation_rate", "prior_nll"
  // positions: [n, J, 3] metres, root-relative (root joint at the origin), protocol skeleton.
  // scores: [n], one per frame, e.g. 1 for a frame with any angle outside its range and 0
  // otherwise (the mean is then the violation rate), or a negative log-likelihood in nats.
  // Scores must be finite (Evaluate throws otherwise).
  std::function<void(const float* positions, int n, double* scores)> score;
};

// Where the body goes (eval/root_motion.h): figures of the futures' world root and feet beside
// the protocol's root-relative ones, which they do not change.
struct RootOptions {
  bool enabled = false;
  UpAxis up;                     // the data's up axis
  std::vector<int> feet;         // joints that touch the ground (the ankles); empty: no skating
  double contact_height = 0.05;  // metres above the ground: the lowest foot of the history
};

struct EvalOptions {
  // K, samples per history; >= 2 (APD is a mean over pairs of samples).
  int num_samples = 50;
  // Window i is predicted with WindowSeed(seed, i): results do not depend on evaluation order.
  uint64_t seed = 0;
  // The controllable setting: index of a part of the skeleton's default partition that every
  // sample shares (the predictor must support it), or -1.
  int fixed_part = -1;
  // false: windows whose multimodal set holds only themselves are left out of every figure (the
  // GSPS script); true: they count (DLow). The protocol config's multimodal.keep_singletons.
  bool keep_singleton_sets = true;
  // Plausibility figures, each reported for predicted frames and for ground-truth frames.
  std::vector<FrameScorer> scorers;
  RootOptions root;
  // Threads measuring windows at once (>= 1). The figures are the same for any number: each
  // window has its own seed and the sums are taken in window order. The predictor's Predict and
  // the scorers are then called from several threads at once (they must not change shared state).
  int threads = 1;
  // Called after each window with (windows done, total), one call at a time; may be empty.
  std::function<void(int done, int total)> progress;
};

// Means over windows: the window metrics (metres) and more (scores: means over frames, in the
// scorer's unit).
struct Figures : WindowMetrics {
  int windows = 0;
  double mean_set_size = 0;  // multimodal set size, the window itself included
  // Controllable setting only (fixed_part >= 0): APD over the pose-vector components of the joints
  // outside the fixed part, and over the fixed part's own (its spread across samples).
  double apd_varied = 0;
  double apd_fixed = 0;
  std::vector<double> predicted_scores;  // [scorers]: mean over all K x t_pred predicted frames
  std::vector<double> truth_scores;      // [scorers]: mean over the t_pred ground-truth frames
  RootFigures root;                      // when EvalOptions::root.enabled
};

struct EvalResult {
  int num_samples = 0;
  uint64_t seed = 0;
  std::string fixed_part;  // part name, "" when none
  Figures overall;
  std::vector<Figures> per_action;        // [test_set.actions.size()]
  std::vector<WindowMetrics> per_window;  // [N]; all zero for a skipped window
  std::vector<char> evaluated;            // [N]: 0 for a window skipped as a singleton
  int windows_skipped = 0;                // singleton sets left out (keep_singleton_sets false)
  double seconds_predicting = 0;          // time inside Predictor::Predict, summed over threads
  double seconds_metrics = 0;             // APD, ADE, FDE, MMADE, MMFDE (+ part APDs)
  double seconds_scoring = 0;             // frame scorers
};

// Throws std::invalid_argument when the predictor's skeleton or lengths differ from the test set's
// (naming both), when the multimodal sets are missing, for K < 2, a fixed part out of range or not
// supported, a scorer without a function, or when every window is skipped; and when the predictor
// returns a non-finite value (naming the window).
EvalResult Evaluate(Predictor& predictor, const TestSet& test_set, const EvalOptions& options);

// The seed window i is predicted with: a SplitMix64 mix of the run's seed and i.
uint64_t WindowSeed(uint64_t seed, int window);

}  // namespace motionfork
