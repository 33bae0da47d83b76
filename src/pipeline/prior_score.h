// `prior score`: a motion's poses under a pose prior, per frame and in summary, on the prior's
// skeleton.
#pragma once

#include <string>
#include <vector>

#include "core/motion.h"
#include "flow/pose_prior.h"
#include "pipeline/motion_input.h"

namespace motionfork::pipeline {

// The motion on the prior's skeleton: as stored, bound by index (.npy), re-ordered by joint names,
// or mapped through the skeleton config the prior was trained with (e.g. a Bandai BVH of 22
// joints onto 17; looked up in config_dir), or, for another rig's names, by their roles
// (ConformForModel; `notes` says how). Throws std::invalid_argument saying what is expected.
Motion OnPriorSkeleton(const LoadedMotion& loaded, const PosePrior& prior,
                       const std::string& config_dir, std::vector<std::string>* notes = nullptr);

struct PriorScore {
  std::vector<double> nll;  // [frames] negative log-likelihood, nats per pose
  double mean = 0, median = 0, min = 0, max = 0;
  int best_frame = 0, worst_frame = 0;
  double held_out_q50 = 0, held_out_q99 = 0;  // what real held-out poses scored (NaN: unknown)
  int above_q99 = 0;                          // frames above held_out_q99 (0 when unknown)
};

// motion: on the prior's skeleton (OnPriorSkeleton), at least one frame.
PriorScore ScorePoses(const PosePrior& prior, const Motion& motion);

}  // namespace motionfork::pipeline
