#include "bundle/manifest.h"

#include "config/skeleton_yaml.h"
#include "config/yaml_util.h"

namespace motionfork {

using yaml_util::Fail;
using yaml_util::Get;

YAML::Node LoadManifestFile(const std::string& path) { return yaml_util::LoadFile(path); }

ManifestHeader ParseManifestHeader(const std::string& path, const YAML::Node& root,
                                   const std::string& expected_format, const ManifestKeys& keys) {
  ManifestHeader h;
  h.format = Get<std::string>(path, root, "format");
  if (h.format != expected_format) {
    Fail(path, root["format"],
         "format: expected '" + expected_format + "', found '" + h.format +
             "' (a bundle from another version?)");
  }
  if (keys.protocol) {
    const YAML::Node p = yaml_util::Section(path, root, "protocol", true);
    h.protocol = Get<std::string>(path, p, "name");
    h.fps = Get<double>(path, p, "fps");
  }
  if (keys.skeleton) h.skeleton = ParseSkeletonSpec(path, root);
  if (const YAML::Node c = root["checksums"]) {
    if (!c.IsMap()) Fail(path, c, "'checksums' must map file names to checksums");
    for (const auto& kv : c) h.checksums[kv.first.as<std::string>()] = kv.second.as<std::string>();
  }
  return h;
}

int ParseManifestVersion(const std::string& path, const YAML::Node& root,
                         const std::string& expected_format, const std::string& what,
                         int max_version) {
  const std::string format = yaml_util::GetOr<std::string>(path, root, "format", "");
  if (format != expected_format) {
    Fail(path, root,
         "expected format '" + expected_format + "' (" + what + "), found '" + format + "'");
  }
  const int version = Get<int>(path, root, "version");
  if (version < 1 || version > max_version) {
    Fail(path, root["version"],
         "bundle version " + std::to_string(version) + " is not readable by this build (reads 1.." +
             std::to_string(max_version) + ")");
  }
  return version;
}

void EmitManifestFormat(YAML::Emitter& out, const ManifestHeader& h, bool open_protocol) {
  out << YAML::Key << "format" << YAML::Value << h.format;
  out << YAML::Key << "protocol" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << h.protocol;
  out << YAML::Key << "fps" << YAML::Value << h.fps;
  if (!open_protocol) out << YAML::EndMap;
}

void EmitManifestChecksums(YAML::Emitter& out, const BundleChecksums& checksums) {
  if (checksums.empty()) return;
  out << YAML::Key << "checksums" << YAML::Value << YAML::BeginMap;
  for (const auto& [file, sum] : checksums) out << YAML::Key << file << YAML::Value << sum;
  out << YAML::EndMap;
}

std::vector<std::pair<std::string, std::string>> ParseManifestInfo(const YAML::Node& root) {
  std::vector<std::pair<std::string, std::string>> info;
  if (const YAML::Node n = root["info"]) {
    for (const auto& kv : n)
      info.emplace_back(kv.first.as<std::string>(), kv.second.as<std::string>());
  }
  return info;
}

void EmitManifestInfo(YAML::Emitter& out,
                      const std::vector<std::pair<std::string, std::string>>& info) {
  out << YAML::Key << "info" << YAML::Value << YAML::BeginMap;
  for (const auto& [k, v] : info) out << YAML::Key << k << YAML::Value << v;
  out << YAML::EndMap;
}

}  // namespace motionfork
