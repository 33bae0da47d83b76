#include "generator/training/training_manifest.h"

#include <stdexcept>

#include "core/heading.h"
#include "generator/training/training_setup.h"

namespace motionfork {

ModelConfig TrainingModelConfig(const GeneratorTrainConfig& config, const ProtocolOptions& protocol,
                                const Skeleton& skeleton, const std::string& split_file) {
  ModelConfig model;
  model.protocol = protocol.name;
  model.fps = protocol.fps;
  model.generator = config.generator;
  model.generator.t_his = protocol.t_his;
  model.generator.t_pred = protocol.t_pred;
  model.generator.num_nodes = skeleton.num_joints() - 1;
  if (config.body_frame) {
    if (protocol.up.empty()) {
      throw std::invalid_argument("generator.body_frame needs the protocol '" + protocol.name +
                                  "' to declare its up axis (up: y)");
    }
    if (!FindHeadingJoints(skeleton)) {
      throw std::invalid_argument("generator.body_frame needs the skeleton '" + skeleton.name() +
                                  "' to name left/right joints (its heading)");
    }
    model.generator.body_frame = protocol.up;
  }
  model.skeleton = skeleton.ToSpec();
  model.info["config"] = config.name;
  model.info["seed"] = std::to_string(config.training.seed);
  model.info["epochs"] = std::to_string(config.training.epochs);
  model.info["split"] = TrainingSplitName(split_file);
  model.info["training_config"] = "training.yaml";
  return model;
}

size_t WindowsWithMultimodalFutures(const TrainingWindows& data) {
  size_t with_mm = 0;
  for (const auto& m : data.multimodal) with_mm += !m.empty();
  return with_mm;
}

}  // namespace motionfork
