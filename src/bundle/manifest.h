// The one manifest parser: the keys every bundle manifest shares (hgvae.yaml, dvae.yaml,
// model.yaml, prior.yaml), read and written here; each bundle's own keys are read by its
// bundle/*_bundle.cc. Every error is a FormatError naming the file, the line and the key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <utility>
#include <vector>

#include "bundle/bundle_files.h"
#include "core/skeleton.h"

namespace motionfork {

struct ManifestHeader {
  std::string format;         // "motionfork-hgvae-1", ...
  std::string protocol;       // protocol.name
  double fps = 0;             // protocol.fps, Hz
  SkeletonSpec skeleton;      // skeleton: the protocol skeleton with its parts
  BundleChecksums checksums;  // checksums: (empty for bundles written before checksums existed)
};

struct ManifestKeys {
  bool protocol = true;  // protocol: {name, fps}
  bool skeleton = true;  // skeleton: {...} (config/skeleton_yaml.h)
};

// Reads a manifest file; FormatError naming the file for unreadable YAML.
YAML::Node LoadManifestFile(const std::string& path);

// format must equal expected_format ("a bundle from another version?" otherwise); the other keys
// as `keys` says; checksums when present.
ManifestHeader ParseManifestHeader(const std::string& path, const YAML::Node& root,
                                   const std::string& expected_format,
                                   const ManifestKeys& keys = {});
// A versioned format (prior.yaml: `format: motionfork-flow-prior`, `version: 1`): the format must
// match (`what` names the kind of bundle) and the version be 1 .. max_version. Returns the version.
int ParseManifestVersion(const std::string& path, const YAML::Node& root,
                         const std::string& expected_format, const std::string& what,
                         int max_version);

// `format` and `protocol: {name, fps}` (without closing the protocol mapping when open_protocol:
// the generator adds t_his and t_pred).
void EmitManifestFormat(YAML::Emitter& out, const ManifestHeader& h, bool open_protocol = false);
// `checksums:` (nothing when empty).
void EmitManifestChecksums(YAML::Emitter& out, const BundleChecksums& checksums);

// `info:` provenance pairs, in file order (absent = none).
std::vector<std::pair<std::string, std::string>> ParseManifestInfo(const YAML::Node& root);
void EmitManifestInfo(YAML::Emitter& out,
                      const std::vector<std::pair<std::string, std::string>>& info);

}  // namespace motionfork
