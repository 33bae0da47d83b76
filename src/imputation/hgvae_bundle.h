// HG-VAE bundles on disk (LibTorch side): DIR/hgvae.yaml (HgvaeManifest) + DIR/hgvae.pt.
#pragma once

#include <string>

#include "imputation/hgvae_net.h"

namespace motionfork {

// Nodes of the full graph for a manifest: 3 per non-root joint.
int HgvaeCoords(const HgvaeManifest& m);

HgvaeNet BuildHgvaeNet(const HgvaeManifest& m);
// Both files written all-or-nothing.
void SaveHgvaeBundle(const std::string& dir, const HgvaeManifest& m, HgvaeNet& net);
// Throws FormatError naming the missing or malformed file. The net is in eval mode.
HgvaeNet LoadHgvaeBundle(const std::string& dir, HgvaeManifest* m);

}  // namespace motionfork
