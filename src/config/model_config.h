// Model bundles' model.yaml: what a saved generator is (protocol settings, network sizes,
// skeleton with its parts) so that a bundle describes itself. Read and written here, the one place
// that handles YAML.
#pragma once

#include <map>
#include <string>

#include "config/generator_options.h"
#include "core/skeleton.h"

namespace motionfork {

constexpr const char* kGeneratorBundleFormat = "motionfork-generator-1";

struct ModelConfig {
  std::string format = kGeneratorBundleFormat;
  std::string protocol;                     // protocol name the model was trained under
  double fps = 0;                           // Hz
  GeneratorOptions generator;               // includes t_his, t_pred, num_nodes, partition
  SkeletonSpec skeleton;                    // the protocol skeleton, parts as joint lists
  std::map<std::string, std::string> info;  // free-form provenance (command, seed, epochs, ...)
};

// Throws FormatError naming the file, line and key.
ModelConfig LoadModelConfig(const std::string& path);
std::string ModelConfigToYaml(const ModelConfig& config);

}  // namespace motionfork
