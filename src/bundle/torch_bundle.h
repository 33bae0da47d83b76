// Shared by the LibTorch bundles (hgvae, dvae, generator): one load path and one way to write a
// module's weights. Used by config and the bundle layer.
#pragma once

#include <torch/torch.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "bundle/bundle_files.h"
#include "core/error.h"

namespace motionfork {

// The one load path of a LibTorch bundle: files present, manifest parsed, weights checked against
// the manifest's checksum and loaded into the net `build` makes from the manifest.
template <typename Manifest, typename Net, typename LoadManifest, typename Build>
Net LoadTorchBundle(const std::string& dir, const std::string& kind, const std::string& yaml_name,
                    const std::string& weights_name, Manifest* m, LoadManifest load_manifest,
                    Build build) {
  RequireBundleFiles(dir, kind, {yaml_name, weights_name});
  BundleChecksums sums;
  *m = load_manifest((std::filesystem::path(dir) / yaml_name).string(), &sums);
  const std::string bytes = ReadBundleFile(dir, weights_name, sums, yaml_name);
  const std::string weights = (std::filesystem::path(dir) / weights_name).string();
  Net net{nullptr};
  try {
    net = build(*m);
    std::istringstream in(bytes);
    torch::load(net, in);
  } catch (const c10::Error& e) {
    throw FormatError(FormatMessage(weights, "",
                                    "cannot load the weights (corrupt, or from a model with other "
                                    "sizes than " +
                                        yaml_name +
                                        " says): " + std::string(e.what_without_backtrace())));
  }
  net->eval();
  return net;
}

template <typename Net>
std::string WeightBytes(Net& net) {
  std::ostringstream weights;
  torch::save(net, weights);
  return weights.str();
}

}  // namespace motionfork
