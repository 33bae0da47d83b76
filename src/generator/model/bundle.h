// Saving and loading generator bundles (LibTorch side).
#pragma once

#include <string>

#include "config/model_config.h"
#include "generator/model/generator_net.h"

namespace motionfork {

// Writes DIR/model.yaml and DIR/generator.pt, each all-or-nothing.
void SaveGeneratorBundle(const std::string& dir, const ModelConfig& config, GeneratorNet& net);

// Builds the network described by DIR/model.yaml and loads DIR/generator.pt into it (eval mode).
// Throws FormatError naming the missing or malformed file.
GeneratorNet LoadGeneratorBundle(const std::string& dir, ModelConfig* config);

}  // namespace motionfork
