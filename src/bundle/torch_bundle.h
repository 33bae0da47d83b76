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
template <typename Manifest, typename LoadManifest, typename Build>
auto LoadTorchBundle(const std::string& dir, const std::string& kind, const std::string& yaml_name,
                     const std::string& weights_name, Manifest* m, LoadManifest load_manifest,
                     Build build) -> decltype(build(*m)) {
  using Net = decltype(build(*m));
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

// The one save path: net's weights as weights_name and, last, the manifest `format` makes of m and
// the weights' checksum as yaml_name (WriteBundle, all-or-nothing).
template <typename Manifest, typename Net, typename Format>
void SaveTorchBundle(const std::string& dir, const std::string& yaml_name,
                     const std::string& weights_name, const Manifest& m, Net& net, Format format) {
  WriteBundle(dir, {{weights_name, WeightBytes(net)}}, yaml_name,
              [&](const BundleChecksums& sums) { return format(m, sums); });
}

}  // namespace motionfork
