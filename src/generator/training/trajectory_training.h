// Training the trajectory network (issue 27; generator/trajectory/trajectory_net.h): the training
// split's windows in the body's frame at their last history frame, their true poses in, their
// root's motion out. Losses (weights in the config's `trajectory` section): the root's mean
// distance over the future frames, its last frame's distance, and foot skating: where a true foot
// touches the ground (within contact_height of the window's lowest ankle, weighted as the
// evaluation's figure, eval/root_motion.h) the predicted root must not make it slide.
#pragma once

#include <string>
#include <vector>

#include "dataset/dataset.h"
#include "generator/model/generator_options.h"
#include "generator/model/training_options.h"
#include "generator/training/training.h"

namespace motionfork {

struct TrajectoryTrainSummary {
  size_t train_windows = 0, validation_windows = 0;
  int kept_epoch = 0;               // 1-based: the epoch whose weights were saved
  double val_ade = 0, val_fde = 0;  // the kept epoch's validation root errors (m); 0 without
  double seconds = 0;
};

// Trains on ds's training split (every validation_every-th training clip held out) for the
// generator `model` describes (its frames, nodes, first part and body frame: model.generator
// .body_frame must be set) and writes out_dir/trajectory/ (trajectory.yaml, trajectory.pt,
// log.csv), all-or-nothing. feet: the ankles' joint indices for the skating term (empty: no
// term). The callbacks' terms: loss, root, final, skating, then val_ade, val_fde. Throws
// std::invalid_argument for a model without a body frame or too few windows.
TrajectoryTrainSummary TrainTrajectory(const TrajectoryTrainOptions& options,
                                       const ModelConfig& model, const Dataset& ds,
                                       const std::vector<int>& feet, const std::string& out_dir,
                                       const TrainCallbacks& callbacks);

// True when out_dir holds a trajectory bundle (trajectory/trajectory.yaml).
bool TrajectoryTrained(const std::string& out_dir);

// What a trajectory run into out_dir did, newline-terminated.
std::string TrajectoryDoneText(const TrajectoryTrainSummary& summary, const std::string& out_dir);

// The train command's last stage: trains into out_dir unless it already holds a trajectory, with
// the skating term's ankles found by the rig conventions in config_dir (config/rig_config.h).
// Returns what it did, newline-terminated (TrajectoryDoneText, or that it was there already).
std::string TrainTrajectoryOnce(const TrajectoryTrainOptions& options, const ModelConfig& model,
                                const Dataset& ds, const std::string& config_dir,
                                const std::string& out_dir, const TrainCallbacks& callbacks);

}  // namespace motionfork
