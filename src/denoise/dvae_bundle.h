// Motion-DVAE bundles on disk (LibTorch side): DIR/dvae.yaml (DvaeManifest) + DIR/dvae.pt.
#pragma once

#include <string>

#include "denoise/dvae_net.h"

namespace motionfork {

int DvaeValues(const DvaeManifest& m);  // joints x 3

DvaeNet BuildDvaeNet(const DvaeManifest& m);
// Both files written all-or-nothing.
void SaveDvaeBundle(const std::string& dir, const DvaeManifest& m, DvaeNet& net);
// Throws FormatError naming the missing or malformed file. The net is in eval mode.
DvaeNet LoadDvaeBundle(const std::string& dir, DvaeManifest* m);

}  // namespace motionfork
