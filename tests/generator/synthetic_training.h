// Shared by the generator's training tests: a tiny synthetic dataset of walking clips, a tiny
// training config and the model config training would write for them.
#pragma once

#include "dataset/dataset.h"
#include "generator/model/training_options.h"
#include "test_support.h"

namespace motionfork::testing {

// A tiny dataset: synthetic walking clips of the test humanoid, split into train/test.
inline Dataset SyntheticDataset(int clips, int frames) {
  Dataset ds;
  ds.protocol.name = "synthetic";
  ds.protocol.fps = 30;
  ds.protocol.t_his = 5;
  ds.protocol.t_pred = 10;
  ds.skeleton.skeleton = MakeHumanoid();
  ds.skeleton.source = ds.skeleton.skeleton;
  for (int c = 0; c < clips; ++c) {
    Clip clip;
    clip.name = "clip" + std::to_string(c);
    clip.split = c % 4 == 3 ? Split::kTest : Split::kTrain;
    clip.motion = MakeWalkingMotion(frames, 30.0, 100 + c);
    ds.clips.push_back(std::move(clip));
  }
  return ds;
}

inline GeneratorTrainConfig TinyConfig() {
  GeneratorTrainConfig c;
  c.name = "tiny";
  c.protocol = "synthetic";
  c.generator.n_pre = 6;
  c.generator.hidden = 32;
  c.generator.blocks = 1;
  c.generator.nz = 4;
  c.losses.diversity = {1, 1};
  c.losses.diversity_scale = {1, 1};
  c.multimodal.last_pose_threshold = 0.2;
  c.multimodal.future_min_distance = 0.0;
  c.multimodal.max_per_window = 3;
  c.training.samples_per_part = {3, 3};
  c.training.batch_histories = 4;
  c.training.epochs = 8;
  c.training.windows_per_epoch = 40;
  c.training.lr_constant_epochs = 8;
  c.training.learning_rate = 3e-3;
  c.training.window_stride = 2;
  return c;
}

inline ModelConfig ModelFor(const Dataset& ds, const GeneratorTrainConfig& c) {
  ModelConfig m;
  m.protocol = ds.protocol.name;
  m.fps = ds.protocol.fps;
  m.generator = c.generator;
  m.generator.t_his = ds.protocol.t_his;
  m.generator.t_pred = ds.protocol.t_pred;
  m.generator.num_nodes = ds.skeleton.skeleton->num_joints() - 1;
  m.skeleton = ds.skeleton.skeleton->ToSpec();
  return m;
}

}  // namespace motionfork::testing
