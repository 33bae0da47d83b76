// A temporal refiner's settings in YAML (refine/refiner_options.h), shared by the bundles that
// carry one (Motion-DVAE, HG-VAE) and their training configs: `refiner:` in a manifest holds the
// model keys; in a config it holds the training keys too.
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>

#include "refine/refiner_options.h"

namespace motionfork {

// The model keys: channels, window, stride, dilations, linear_reach, smooth_start.
const std::set<std::string>& RefinerModelKeys();
// The training keys besides them: epochs, windows_per_epoch, batch_size, learning_rate, lr_decay,
// grad_clip, patience, seed, threads.
const std::set<std::string>& RefinerTrainKeys();

// Keys present in n over o (missing ones keep o's values), validated; errors name file and line.
void ParseRefinerModel(const std::string& file, const YAML::Node& n, RefinerOptions* o);
void ParseRefinerTraining(const std::string& file, const YAML::Node& n, RefinerTrainOptions* o);
// A manifest's optional `refiner:` section (model keys only) into o; absent: o unchanged.
void ParseManifestRefiner(const std::string& file, const YAML::Node& root, RefinerOptions* o);
// Emits `refiner:` with the model keys (smooth_start only when false) when o is enabled (bundles
// without one stay as they were).
void EmitManifestRefiner(YAML::Emitter& out, const RefinerOptions& o);

}  // namespace motionfork
