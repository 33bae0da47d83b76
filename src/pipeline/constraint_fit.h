// `constraints fit`: every constraint's range from the training split of a protocol's data (a low
// and a high percentile of the angle, widened by a margin), as a constraint YAML whose header says
// how it was made, with a first look at the held-out test split.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "constraints/constraint_set.h"
#include "constraints/constraint_spec.h"
#include "constraints/fit.h"
#include "core/progress.h"
#include "dataset/protocol_options.h"

namespace motionfork::pipeline {

struct ConstraintFitRequest {
  std::string protocol;     // name or YAML path
  std::string data;         // the protocol's data folder
  std::string constraints;  // definitions (name or YAML path); "" = named like the skeleton
  std::string split_file;   // "" = the protocol's
  FitOptions fit;
  // Also fit once per subject of the training split (Bandai: style; Human3.6M: subject) on the
  // other subjects' clips, and measure the left-out subject's frames against those ranges: how
  // the ranges hold on motion of a kind they never saw.
  bool leave_one_out = false;
  std::string command_line;  // the command that reproduces the fit, for the file's header
  std::string config_dir, cache_dir;
  StageProgress progress;  // loading, measuring angles
};

// Frames of some clips measured against a fitted set.
struct FrameCheck {
  long long frames = 0;
  long long flagged = 0;              // frames outside some range or with an undefined angle
  std::vector<long long> violations;  // [fitted constraints] frames outside that range
};

// One subject left out of the fit (ConstraintFitRequest::leave_one_out).
struct LeftOutSubject {
  std::string subject;  // "" for clips without one
  long long clips = 0;
  std::vector<FittedRange> ranges;  // fitted on the other subjects
  FrameCheck check;                 // this subject's frames against them
};

struct ConstraintFit {
  ProtocolOptions protocol;
  ConstraintSetSpec definitions;
  std::optional<ConstraintSet> fitted;  // bound to the protocol skeleton
  std::vector<FittedRange> ranges;      // [definitions.constraints.size()]
  long long train_frames = 0;
  FrameCheck test;                       // the held-out test split (frames 0: none)
  std::vector<LeftOutSubject> left_out;  // by subject name, when asked
  std::string yaml;                      // the constraint YAML to write
};

// The left-out subject whose frames the ranges flag most (share in percent); nullptr when none.
const LeftOutSubject* MostFlaggedLeftOut(const ConstraintFit& fit, double* percent);

// Throws std::invalid_argument for bad fit options, definitions that do not bind to the
// skeleton (before the dataset is read), a data folder without training clips, or
// leave_one_out with fewer than two training subjects.
ConstraintFit FitConstraints(const ConstraintFitRequest& request);

}  // namespace motionfork::pipeline
