// The one manifest parser: the keys every bundle manifest shares (hgvae.yaml, dvae.yaml,
// model.yaml, prior.yaml), read and written here; each bundle's own keys are read by its
// bundle/*_bundle.cc. Every error is a FormatError naming the file, the line and the key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
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
// ParseManifestHeader into a manifest struct with members format, protocol, fps and skeleton
// (HgvaeManifest, DvaeManifest); the checksums into *checksums when it is given.
template <typename Manifest>
void ParseManifestHeaderInto(const std::string& path, const YAML::Node& root,
                             const std::string& expected_format, Manifest* m,
                             BundleChecksums* checksums) {
  ManifestHeader h = ParseManifestHeader(path, root, expected_format);
  m->format = h.format;
  m->protocol = h.protocol;
  m->fps = h.fps;
  m->skeleton = std::move(h.skeleton);
  if (checksums) *checksums = std::move(h.checksums);
}

// A versioned format (prior.yaml: `format: motionfork-flow-prior`, `version: 1`): the format must
// match (`what` names the kind of bundle) and the version be 1 .. max_version. Returns the version.
int ParseManifestVersion(const std::string& path, const YAML::Node& root,
                         const std::string& expected_format, const std::string& what,
                         int max_version);

// `format` and `protocol: {name, fps}` (without closing the protocol mapping when open_protocol:
// the generator adds t_his and t_pred).
void EmitManifestFormat(YAML::Emitter& out, const ManifestHeader& h, bool open_protocol = false);
// The whole manifest of a bundle: `format` and `protocol` of h, what `keys` writes (the bundle's
// own keys), h's `skeleton` and `checksums`, then `info`; doubles with 17 digits, a final newline.
std::string FormatManifest(const ManifestHeader& h,
                           const std::vector<std::pair<std::string, std::string>>& info,
                           const std::function<void(YAML::Emitter&)>& keys);
// `checksums:` (nothing when empty).
void EmitManifestChecksums(YAML::Emitter& out, const BundleChecksums& checksums);

// `normalisation: {mean, std}`, each a list of `values` numbers (otherwise a FormatError "expected
// <values> means and stds (<per_value>)").
void ParseManifestNormalisation(const std::string& path, const YAML::Node& root, int values,
                                const std::string& per_value, std::vector<double>* mean,
                                std::vector<double>* std);
void EmitManifestNormalisation(YAML::Emitter& out, const std::vector<double>& mean,
                               const std::vector<double>& std);

// `info:` provenance pairs, in file order (absent = none).
std::vector<std::pair<std::string, std::string>> ParseManifestInfo(const YAML::Node& root);
void EmitManifestInfo(YAML::Emitter& out,
                      const std::vector<std::pair<std::string, std::string>>& info);
// key = value in info: an earlier entry of key goes, the new one comes last.
void SetManifestInfo(std::vector<std::pair<std::string, std::string>>* info, const std::string& key,
                     const std::string& value);

}  // namespace motionfork
