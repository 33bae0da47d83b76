// Small helpers for reading YAML with errors that name the file, line and key. Private to the
// config module (not installed in any other module's headers).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "core/error.h"

namespace motionfork::yaml_util {

inline std::string Where(const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  return m.line >= 0 ? "line " + std::to_string(m.line + 1) : "";
}

[[noreturn]] inline void Fail(const std::string& file, const YAML::Node& node,
                              const std::string& what) {
  throw FormatError(FormatMessage(file, Where(node), what));
}

inline YAML::Node LoadFile(const std::string& file) {
  try {
    YAML::Node root = YAML::LoadFile(file);
    if (!root.IsMap()) {
      throw FormatError(FormatMessage(file, "", "expected a YAML mapping at the top level"));
    }
    return root;
  } catch (const YAML::BadFile&) {
    throw FormatError(FormatMessage(file, "", "cannot open the file"));
  } catch (const YAML::Exception& e) {
    throw FormatError(FormatMessage(file, "line " + std::to_string(e.mark.line + 1), e.msg));
  }
}

template <typename T>
T Get(const std::string& file, const YAML::Node& map, const std::string& key) {
  const YAML::Node n = map[key];
  if (!n) Fail(file, map, "missing key '" + key + "'");
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    Fail(file, n, "key '" + key + "' has the wrong type (value: " + YAML::Dump(n) + ")");
  }
}

template <typename T>
T GetOr(const std::string& file, const YAML::Node& map, const std::string& key, T fallback) {
  const YAML::Node n = map[key];
  if (!n || n.IsNull()) return fallback;
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    Fail(file, n, "key '" + key + "' has the wrong type (value: " + YAML::Dump(n) + ")");
  }
}

inline std::vector<std::string> StringList(const std::string& file, const YAML::Node& n,
                                           const std::string& key) {
  if (!n) return {};
  if (!n.IsSequence()) Fail(file, n, "key '" + key + "' must be a list");
  std::vector<std::string> out;
  for (const YAML::Node& e : n) {
    if (!e.IsScalar()) Fail(file, e, "key '" + key + "' must be a list of names");
    out.push_back(e.as<std::string>());
  }
  return out;
}

}  // namespace motionfork::yaml_util
