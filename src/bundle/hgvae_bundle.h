// HG-VAE bundles: DIR/hgvae.yaml (HgvaeManifest) + DIR/hgvae.pt, and the HG-VAE training configs
// (configs/models/hgvae_*.yaml) <-> structs (imputation/hgvae_options.h). A missing key takes its
// default, an unknown key is an error (a typo would otherwise keep a default); every error is a
// FormatError naming the file and line.
#pragma once

#include <string>

#include "bundle/bundle_files.h"
#include "bundle/torch_bundle.h"
#include "core/skeleton.h"
#include "dataset/protocol_options.h"
#include "imputation/hgvae_model.h"
#include "imputation/hgvae_net.h"
#include "imputation/hgvae_options.h"

namespace motionfork {

HgvaeTrainConfig LoadHgvaeTrainConfig(const std::string& path);
HgvaeTrainConfig ParseHgvaeTrainConfig(const std::string& yaml_text,
                                       const std::string& source_name);

// checksums: the manifest's file checksums (none for bundles written before they existed).
HgvaeManifest LoadHgvaeManifest(const std::string& path, BundleChecksums* checksums = nullptr);
// Parsing the result gives the manifest back exactly (doubles with 17 digits).
std::string FormatHgvaeManifest(const HgvaeManifest& manifest,
                                const BundleChecksums& checksums = {});

// Both files written all-or-nothing (bundle/bundle_files.h), hgvae.pt's checksum in hgvae.yaml.
void SaveHgvaeBundle(const std::string& dir, const HgvaeManifest& m, HgvaeNet& net);
// Verified as bundle/torch_bundle.h says; throws FormatError naming the missing, malformed or
// mismatching file. The net is in eval mode.
HgvaeNet LoadHgvaeBundle(const std::string& dir, HgvaeManifest* m,
                         BundleCheck check = BundleCheck::kStrict);
// Reads DIR/hgvae.yaml and DIR/hgvae.pt (was HgvaeModel::Load).
HgvaeModel LoadHgvaeModel(const std::string& dir);
// Rewrites DIR/hgvae.yaml with m, keeping the recorded checksums.
void RewriteHgvaeManifest(const std::string& dir, const HgvaeManifest& m);

// The manifest of the bundle a training run with `config` on `protocol` writes: the protocol's
// timing and skeleton (`skeleton`, the protocol's) and the recipe's provenance
// (bundle/protocol_manifest.h), with the config's out-of-distribution rule and imputation defaults.
HgvaeManifest HgvaeTrainingManifest(const HgvaeTrainConfig& config, const ProtocolOptions& protocol,
                                    const Skeleton& skeleton);

}  // namespace motionfork
