// HG-VAE training configs (configs/models/hgvae_*.yaml) and bundles' hgvae.yaml <-> structs
// (imputation/hgvae_options.h). A missing key takes its default, an unknown key is an error (a
// typo would otherwise keep a default); every error is a FormatError naming the file and line.
#pragma once

#include <string>

#include "imputation/hgvae_options.h"

namespace motionfork {

HgvaeTrainConfig LoadHgvaeTrainConfig(const std::string& path);
HgvaeTrainConfig ParseHgvaeTrainConfig(const std::string& yaml_text,
                                       const std::string& source_name);

HgvaeManifest LoadHgvaeManifest(const std::string& path);
// Parsing the result gives the manifest back exactly (doubles with 17 digits).
std::string FormatHgvaeManifest(const HgvaeManifest& manifest);

// Throws std::invalid_argument naming the field and the rule it broke. num_coords: nodes of the
// full graph (0 = not known yet: levels may still say 0).
void ValidateHgvaeOptions(const HgvaeOptions& o, int num_coords);
// Levels with 0 nodes -> num_coords, window 0 -> t_his; validated.
HgvaeOptions ResolveHgvaeOptions(HgvaeOptions o, int num_coords, int t_his);
ImputeObjective ParseImputeObjective(const std::string& text);  // "posterior" | "joint"

}  // namespace motionfork
