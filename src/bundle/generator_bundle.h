// Generator bundles: DIR/model.yaml (ModelConfig) + DIR/generator.pt, optionally
// DIR/constraints.yaml (the angle ranges predictions are repaired to) and DIR/prior/; and the
// generator training configs (configs/models/*.yaml) <-> structs (generator/model/*_options.h).
// Every error is a FormatError naming the file and line. No LibTorch in this header (as
// forecaster.h); the network's side is bundle/generator_net_bundle.h.
#pragma once

#include <string>

#include "bundle/bundle_files.h"
#include "generator/inference/forecaster.h"
#include "generator/model/generator_options.h"
#include "generator/model/training_options.h"

namespace motionfork {

GeneratorTrainConfig LoadGeneratorTrainConfig(const std::string& path);

// checksums: the manifest's file checksums (none for bundles written before they existed).
ModelConfig LoadGeneratorManifest(const std::string& path, BundleChecksums* checksums = nullptr);
std::string FormatGeneratorManifest(const ModelConfig& config,
                                    const BundleChecksums& checksums = {});

// The bundle as a Forecaster, its constraints.yaml (when there is one) repairing predictions (was
// Forecaster::Load) and its trajectory/ (when there is one, bundle/trajectory_bundle.h) moving
// the futures' root. Throws FormatError naming the missing or malformed file.
Forecaster LoadForecaster(const std::string& dir);

}  // namespace motionfork
