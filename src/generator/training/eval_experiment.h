// The `motionfork eval` experiment: a predictor (a baseline or a trained generator bundle) on a
// protocol's test windows (or a folder of clips) -> APD, ADE, FDE, MMADE, MMFDE overall and per
// action, with the plausibility figures of the protocol's constraints and prior when shipped.
// It lives with generator training because it builds the learned predictor (GeneratorPredictor);
// src/eval itself does not depend on the generator.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/progress.h"
#include "dataset/protocol_options.h"
#include "eval/baselines.h"
#include "eval/clip_folder.h"
#include "eval/evaluate.h"
#include "generator/kernels/precision.h"

namespace motionfork {

struct EvalExperimentOptions {
  std::string baseline;              // zero-velocity | constant-velocity | nearest-neighbours
                                     // (aliases: zero, cv, nn, ...); or
  std::string model;                 // a generator bundle folder; exactly one of the two
  std::string protocol;              // protocol name or YAML path (looked up in config_dir)
  std::string data;                  // the protocol's data folder ("" only with clips)
  std::string subset = "test";       // clips of `data` evaluated: test, train or all
  std::string split_file;            // overrides the protocol's split file; "" = the protocol's
  std::string clips;                 // evaluate this folder of motion files instead; "" = data
  ClipConform conform_clips;         // how their joints reach the skeleton (eval/clip_folder.h)
  double turn_degrees = 0;           // the test clips turned about the protocol's up axis first
                                     // (which way they face; training clips stay as recorded)
  int k = 50;                        // futures per history, >= 2
  ConstantVelocityOptions velocity;  // constant-velocity (eval/baselines.h)
  uint64_t seed = 0;
  std::string fix;     // a part of the default partition shared by every sample; ""
  bool repair = true;  // learned predictor: the bundle's angle-range repair
  Precision precision = Precision::kAuto;  // learned predictor: its products (precision.h)
  std::string constraints;  // "" = the protocol's shipped set when there is one; "none" = off
  std::string prior;        // "" = <models_dir>/prior-<protocol> when shipped; "none" = off
  std::string config_dir;   // protocols/, skeletons/, constraints/
  std::string models_dir;   // where shipped priors are looked up
  std::string cache_dir;    // parsed datasets and multimodal sets; "" = none
  int threads = 0;          // windows measured at once; 0 = every core (LibTorch pinned to 1 each)
  StageProgress progress;   // loading, reading clips, evaluating
};

struct EvalExperiment {
  ProtocolOptions protocol;
  std::string test_source;           // "split 'test' of DIR" or the clips folder
  int windows = 0;                   // test windows
  int clips = 0;                     // clips they come from
  int pose_dims = 0;                 // numbers per pose vector
  std::vector<std::string> actions;  // [result.per_action.size()]
  bool multimodal_cached = false;
  std::string predictor_name, predictor_description, bundle_hash;
  bool learned = false;                   // a generator bundle, not a baseline
  int training_windows = -1;              // nearest-neighbours: its training windows; else -1
  bool overlaps_training = false;         // nearest-neighbours evaluated on training windows
  std::string scorers_described;          // "angles: PATH; prior: DIR", or ""
  std::vector<std::string> scorer_names;  // [result.overall.predicted_scores.size()]
  bool root_figures = false;              // Figures::root measured (the protocol's up axis known)
  std::string feet;                       // joints the skating figures watch ("" = none)
  EvalResult result;
  double seconds_loading = 0, seconds_multimodal = 0, seconds_predictor_setup = 0;
  double seconds_total = 0;
};

// Whether a run's figures compare with the protocol's published ones (K = 50 on the protocol's own
// whole test split, no fixed part); else what differs ("K = 20", "a clips folder", ...).
std::vector<std::string> DifferencesFromPublished(const EvalExperimentOptions& options,
                                                  const EvalExperiment& x);
// The figures (of apd, ade, fde, mmade, mmfde) where `ours` beats `published` (APD: higher; the
// rest: lower).
std::vector<std::string> FiguresLeading(const Figures& ours, const PublishedFigures& published);

// The baselines' canonical name for an alias; throws std::invalid_argument naming the known ones.
std::string CanonicalBaseline(const std::string& name);

// Validates the options before loading anything (std::invalid_argument naming the flag), then
// loads, builds the test windows and their multimodal sets, and evaluates.
EvalExperiment RunEvalExperiment(const EvalExperimentOptions& options);

}  // namespace motionfork
