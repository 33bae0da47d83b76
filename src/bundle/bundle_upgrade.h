// Rewrites bundles written before motionfork verified its bundles (bundle/torch_bundle.h): the
// same weights and settings, now with the weights file's checksum in the manifest and the
// manifest's model-defining part in the weights file. `motionfork bundle upgrade` runs it.
#pragma once

#include <string>
#include <vector>

namespace motionfork {

// The generator, HG-VAE and Motion-DVAE bundles in dir and in its immediate subfolders (a model
// folder's hgvae/ and dvae/), each read with its tensors verified against its manifest and written
// anew (all-or-nothing per bundle; other files stay). Returns a line per bundle rewritten
// ("models/bandai: generator"); throws FormatError naming the first bundle that cannot be read,
// std::invalid_argument when dir holds none.
std::vector<std::string> UpgradeBundles(const std::string& dir);

}  // namespace motionfork
