// Motion-DVAE bundles: DIR/dvae.yaml (DvaeManifest) + DIR/dvae.pt, and the Motion-DVAE training
// configs (configs/models/dvae_*.yaml) <-> structs (denoise/dvae_options.h). A missing key takes
// its default, an unknown key is an error; every error is a FormatError naming the file and line.
#pragma once

#include <string>

#include "bundle/bundle_files.h"
#include "bundle/torch_bundle.h"
#include "core/skeleton.h"
#include "dataset/protocol_options.h"
#include "denoise/dvae_model.h"
#include "denoise/dvae_net.h"
#include "denoise/dvae_options.h"

namespace motionfork {

DvaeTrainConfig LoadDvaeTrainConfig(const std::string& path);
DvaeTrainConfig ParseDvaeTrainConfig(const std::string& yaml_text, const std::string& source_name);

// checksums: the manifest's file checksums (none for bundles written before they existed).
DvaeManifest LoadDvaeManifest(const std::string& path, BundleChecksums* checksums = nullptr);
// Parsing the result gives the manifest back exactly (doubles with 17 digits).
std::string FormatDvaeManifest(const DvaeManifest& manifest, const BundleChecksums& checksums = {});

// Both files written all-or-nothing (bundle/bundle_files.h), dvae.pt's checksum in dvae.yaml.
void SaveDvaeBundle(const std::string& dir, const DvaeManifest& m, DvaeNet& net);
// Verified as bundle/torch_bundle.h says; throws FormatError naming the missing, malformed or
// mismatching file. The net is in eval mode.
DvaeNet LoadDvaeBundle(const std::string& dir, DvaeManifest* m,
                       BundleCheck check = BundleCheck::kStrict);
// Reads DIR/dvae.yaml and DIR/dvae.pt (was DvaeModel::Load).
DvaeModel LoadDvaeModel(const std::string& dir);

// The manifest of the bundle a training run with `config` on `protocol` writes: the protocol's
// timing and skeleton (`skeleton`, the protocol's) and the recipe's provenance
// (bundle/protocol_manifest.h), with the config's noise prior and denoising defaults.
DvaeManifest DvaeTrainingManifest(const DvaeTrainConfig& config, const ProtocolOptions& protocol,
                                  const Skeleton& skeleton);

}  // namespace motionfork
