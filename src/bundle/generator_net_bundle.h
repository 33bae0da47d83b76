// Generator bundles, the LibTorch side: the network written to and read from DIR/generator.pt with
// DIR/model.yaml (bundle/generator_bundle.h has the rest). Implemented in generator_bundle.cc.
#pragma once

#include <string>

#include "bundle/generator_bundle.h"
#include "bundle/torch_bundle.h"
#include "generator/model/generator_net.h"

namespace motionfork {

// Both files written all-or-nothing (bundle/bundle_files.h), generator.pt's checksum in
// model.yaml.
void SaveGeneratorBundle(const std::string& dir, const ModelConfig& config, GeneratorNet& net);

// Builds the network described by DIR/model.yaml and loads DIR/generator.pt into it (eval mode).
// Verified as bundle/torch_bundle.h says; throws FormatError naming the missing, malformed or
// mismatching file.
GeneratorNet LoadGeneratorBundle(const std::string& dir, ModelConfig* config,
                                 BundleCheck check = BundleCheck::kStrict);

}  // namespace motionfork
