// Motion-DVAE training configs (configs/models/dvae_*.yaml) and bundles' dvae.yaml <-> structs
// (denoise/dvae_options.h). A missing key takes its default, an unknown key is an error; every
// error is a FormatError naming the file and line.
#pragma once

#include <string>

#include "denoise/dvae_options.h"

namespace motionfork {

DvaeTrainConfig LoadDvaeTrainConfig(const std::string& path);
DvaeTrainConfig ParseDvaeTrainConfig(const std::string& yaml_text, const std::string& source_name);

DvaeManifest LoadDvaeManifest(const std::string& path);
// Parsing the result gives the manifest back exactly (doubles with 17 digits).
std::string FormatDvaeManifest(const DvaeManifest& manifest);

DenoiseMode ParseDenoiseMode(const std::string& text);  // "regression" | "optimisation"
// Throws std::invalid_argument naming the field and the rule it broke.
void ValidateDvaeOptions(const DvaeOptions& o);

}  // namespace motionfork
