#include "bundle/manifest.h"

#include <algorithm>

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

std::string FormatManifest(const ManifestHeader& h,
                           const std::vector<std::pair<std::string, std::string>>& info,
                           const std::function<void(YAML::Emitter&)>& keys) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  EmitManifestFormat(out, h);
  keys(out);
  EmitSkeletonSpec(out, h.skeleton);
  EmitManifestChecksums(out, h.checksums);
  EmitManifestInfo(out, info);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void EmitManifestChecksums(YAML::Emitter& out, const BundleChecksums& checksums) {
  if (checksums.empty()) return;
  out << YAML::Key << "checksums" << YAML::Value << YAML::BeginMap;
  for (const auto& [file, sum] : checksums) out << YAML::Key << file << YAML::Value << sum;
  out << YAML::EndMap;
}

void ParseManifestNormalisation(const std::string& path, const YAML::Node& root, int values,
                                const std::string& per_value, std::vector<double>* mean,
                                std::vector<double>* std) {
  const YAML::Node norm = yaml_util::Section(path, root, "normalisation", true);
  *mean = Get<std::vector<double>>(path, norm, "mean");
  *std = Get<std::vector<double>>(path, norm, "std");
  if (static_cast<int>(mean->size()) != values || static_cast<int>(std->size()) != values) {
    Fail(path, norm,
         "normalisation: expected " + std::to_string(values) + " means and stds (" + per_value +
             ")");
  }
}

void EmitManifestNormalisation(YAML::Emitter& out, const std::vector<double>& mean,
                               const std::vector<double>& std) {
  out << YAML::Key << "normalisation" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "mean" << YAML::Value << YAML::Flow << mean;
  out << YAML::Key << "std" << YAML::Value << YAML::Flow << std;
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

void SetManifestInfo(std::vector<std::pair<std::string, std::string>>* info, const std::string& key,
                     const std::string& value) {
  info->erase(
      std::remove_if(info->begin(), info->end(), [&](const auto& kv) { return kv.first == key; }),
      info->end());
  info->emplace_back(key, value);
}

}  // namespace motionfork
