// Training data of the pose prior: single frames of a protocol's clips as unit limb directions.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/motion.h"
#include "dataset/dataset.h"
#include "flow/flow_options.h"

namespace motionfork {

// Poses as unit limb directions: [N, dim] float32, limb k of a pose ends at joint k + 1.
struct PriorFrames {
  int dim = 0;
  std::vector<float> directions;
  int64_t size() const { return dim > 0 ? static_cast<int64_t>(directions.size()) / dim : 0; }
};

struct PriorData {
  PriorFrames train;     // training-split clips not held out
  PriorFrames held_out;  // a share of the training-split clips (whole clips), for per-epoch NLL
  PriorFrames test;      // the protocol's test split (reported once, never used for choices)
  std::vector<double> bone_lengths;         // [J-1] metres, mean over `train`
  std::vector<std::string> held_out_clips;  // names, sorted
  int train_clips = 0;
  int64_t dropped_frames = 0;  // frames with a bone shorter than 1e-6 m (no direction)
};

// Every frame_stride-th frame of each clip as limb directions, appended to out (the motions must
// share one skeleton). Frames with a zero-length bone are skipped; returns how many.
int64_t AppendDirections(const Motion& motion, int frame_stride, PriorFrames* out,
                         std::vector<double>* length_sums = nullptr,
                         int64_t* length_count = nullptr);

// Splits the dataset's training clips into train and held-out (options.held_out_share of the clips,
// chosen by options.seed independently of clip order) and collects every
// options.frame_stride-th frame; the test split's clips give `test`. Throws std::invalid_argument
// when the training split is empty.
PriorData MakePriorData(const Dataset& dataset, const PriorTrainOptions& options);

}  // namespace motionfork
