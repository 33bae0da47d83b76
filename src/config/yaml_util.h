// Small helpers for reading YAML with errors that name the file, line and key. Private to the
// config module (not installed in any other module's headers).
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/file_util.h"

namespace motionfork::yaml_util {

inline std::string Where(const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  return m.line >= 0 ? "line " + std::to_string(m.line + 1) : "";
}

[[noreturn]] inline void Fail(const std::string& file, const YAML::Node& node,
                              const std::string& what) {
  throw FormatError(FormatMessage(file, Where(node), what));
}

// A YAML exception as a FormatError naming the file and the line.
inline FormatError YamlError(const std::string& file, const YAML::Exception& e) {
  return FormatError(FormatMessage(file, "line " + std::to_string(e.mark.line + 1), e.msg));
}

// Regular files only (io/file_util.h: a FIFO or a folder is refused, never waited on).
inline YAML::Node LoadFile(const std::string& file) {
  const std::string text = ReadFileBytes(file, RequireTextHead(file, "a YAML text file"));
  try {
    YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) {
      throw FormatError(FormatMessage(file, "", "expected a YAML mapping at the top level"));
    }
    return root;
  } catch (const YAML::Exception& e) {
    throw YamlError(file, e);
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

// YAML text (not a file) as a mapping; source names it in errors.
inline YAML::Node LoadText(const std::string& text, const std::string& source) {
  try {
    YAML::Node root = YAML::Load(text);
    if (!root.IsMap())
      throw FormatError(FormatMessage(source, "", "expected a YAML mapping at the top level"));
    return root;
  } catch (const YAML::Exception& e) {
    throw YamlError(source, e);
  }
}

// Rejects keys outside `known` (typos would otherwise silently keep a default).
inline void CheckKeys(const std::string& file, const YAML::Node& map, const std::string& section,
                      const std::set<std::string>& known) {
  for (const auto& kv : map) {
    const std::string key = kv.first.as<std::string>();
    if (known.count(key)) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    Fail(file, kv.first,
         "unknown key '" + (section.empty() ? key : section + "." + key) + "' (known: " + list +
             ")");
  }
}

inline YAML::Node Section(const std::string& file, const YAML::Node& root, const std::string& key,
                          bool required) {
  const YAML::Node n = root[key];
  if (!n || n.IsNull()) {
    if (required) Fail(file, root, "missing mapping '" + key + "'");
    return YAML::Node(YAML::NodeType::Map);
  }
  if (!n.IsMap()) Fail(file, n, "key '" + key + "' must be a mapping");
  return n;
}

// Emits the pairs (key, value, key, value, ...) into the map being written.
inline void EmitPairs(YAML::Emitter&) {}
template <typename Value, typename... Rest>
void EmitPairs(YAML::Emitter& out, const char* key, const Value& value, const Rest&... rest) {
  out << YAML::Key << key << YAML::Value << value;
  EmitPairs(out, rest...);
}

// Emits `key:` with a block mapping of the pairs (key, value, ...), in the order given.
template <typename... Pairs>
void EmitMap(YAML::Emitter& out, const char* key, const Pairs&... pairs) {
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  EmitPairs(out, pairs...);
  out << YAML::EndMap;
}

// Runs f, turning std::invalid_argument and YAML exceptions into FormatErrors naming file.
template <typename F>
auto WithFormatErrors(const std::string& file, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(file, "", e.what()));
  } catch (const YAML::Exception& e) {
    throw YamlError(file, e);
  }
}

}  // namespace motionfork::yaml_util
