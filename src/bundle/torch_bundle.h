// Shared by the LibTorch bundles (generator, HG-VAE, Motion-DVAE): one save path and one verified
// load path.
//
// A bundle proves what it is on load:
// - the manifest records the weights file's checksum (bundle_files.h), so damaged or swapped
//   weights are refused;
// - the weights file records the manifest's model-defining part (the bundle kind's `signature`:
//   sizes, skeleton, frame rate, normalisation; not the settings a user may edit, such as default
//   imputation steps), so an edited manifest that no longer describes the weights is refused;
// - every tensor of the file is checked by name and shape against the network the manifest builds
//   before any weight is copied, so no later code sees a tensor of another size than the manifest
//   says.
// Each failure is a FormatError naming the file, and the key or tensor, expected and found.
#pragma once

#include <torch/torch.h>

#include <filesystem>
#include <memory>
#include <string>

#include "bundle/bundle_files.h"

namespace motionfork {

// A LibTorch bundle kind's file names, and its name in messages ("HG-VAE").
struct TorchBundleNames {
  const char* kind;
  const char* manifest;
  const char* weights;
};

// How strictly a bundle is read. kLegacy accepts a bundle written before checksums and signatures
// (motionfork bundle upgrade reads one that way to write it anew); tensors are verified either way.
enum class BundleCheck { kStrict, kLegacy };

// The weights file's bytes: net's tensors and the manifest signature.
std::string WeightBytes(torch::nn::Module& net, const std::string& signature);

// A bundle's weights file (`bytes`, the file names.weights of dir) read and checked against the
// signature of its manifest, before the network the manifest describes is built: an edited
// manifest is refused before anything of its sizes is allocated.
class VerifiedWeights {
 public:
  VerifiedWeights(const std::string& bytes, const std::string& dir, const TorchBundleNames& names,
                  const std::string& signature, BundleCheck check);
  ~VerifiedWeights();
  // Checks every tensor's name and shape against net's, then copies them into net.
  void LoadInto(torch::nn::Module& net) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// VerifiedWeights(...).LoadInto(net).
void LoadVerifiedWeights(torch::nn::Module& net, const std::string& bytes, const std::string& dir,
                         const TorchBundleNames& names, const std::string& signature,
                         BundleCheck check);

// The one load path of a LibTorch bundle: files present, manifest parsed, weights checked against
// the manifest's checksum and its signature, and verified tensor by tensor as they are loaded into
// the net `build` makes from the manifest.
template <typename Manifest, typename LoadManifest, typename Build, typename Signature>
auto LoadTorchBundle(const std::string& dir, const TorchBundleNames& names, Manifest* m,
                     LoadManifest load_manifest, Build build, Signature signature,
                     BundleCheck check = BundleCheck::kStrict) -> decltype(build(*m)) {
  using Net = decltype(build(*m));
  RequireBundleFiles(dir, names.kind, {names.manifest, names.weights});
  BundleChecksums sums;
  *m = load_manifest((std::filesystem::path(dir) / names.manifest).string(), &sums);
  if (check == BundleCheck::kStrict) RequireChecksum(dir, names.weights, sums, names.manifest);
  const std::string bytes = ReadBundleFile(dir, names.weights, sums, names.manifest);
  const VerifiedWeights weights(bytes, dir, names, signature(*m), check);
  Net net = build(*m);
  weights.LoadInto(*net);
  net->eval();
  return net;
}

// The one save path: net's weights (with the manifest's signature) as names.weights and, last, the
// manifest `format` makes of m and the weights' checksum as names.manifest (WriteBundle,
// all-or-nothing).
template <typename Manifest, typename Net, typename Format, typename Signature>
void SaveTorchBundle(const std::string& dir, const TorchBundleNames& names, const Manifest& m,
                     Net& net, Format format, Signature signature) {
  WriteBundle(dir, {{names.weights, WeightBytes(*net, signature(m))}}, names.manifest,
              [&](const BundleChecksums& sums) { return format(m, sums); });
}

}  // namespace motionfork
