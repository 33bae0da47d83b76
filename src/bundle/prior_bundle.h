// Pose-prior configs (configs/models/flow_prior.yaml) and prior bundles (prior.yaml) <-> structs.
//
// A config has two mappings, `model` and `training`, with the keys of FlowOptions and
// PriorTrainOptions (flow/flow_options.h); a missing key takes its default (GSPS's released code),
// an unknown key is an error (it is probably a typo). Every error is a FormatError naming the file,
// the line and the key.
#pragma once

#include <string>

#include "flow/flow_options.h"
#include "flow/pose_prior.h"

namespace motionfork {

PriorConfig LoadFlowConfig(const std::string& path);
// Same from YAML text; source_name names it in error messages.
PriorConfig ParseFlowConfig(const std::string& yaml_text, const std::string& source_name);
// FormatFlowConfig (flow/flow_options.h) writes a config; parsing its text gives it back exactly.

// A bundle's prior.yaml. Throws FormatError for another format, a newer version, or a missing or
// mistyped key (naming the line).
PriorManifest ParsePriorManifest(const std::string& yaml_text, const std::string& source_name);
// Parsing the result gives the manifest back exactly (doubles written with 17 digits).
std::string FormatPriorManifest(const PriorManifest& manifest);

// Reads DIR/prior.yaml and its weights (was PosePrior::Load). Throws FormatError naming the file
// and what is wrong (unknown format or version, a parameter of the wrong shape, a checksum
// mismatch, ...).
PosePrior LoadPosePrior(const std::string& dir);
// Writes DIR/weights.npy and DIR/prior.yaml all-or-nothing (bundle/bundle_files.h), creating DIR
// (was PosePrior::Save).
void SavePosePrior(const PosePrior& prior, const std::string& dir);

}  // namespace motionfork
