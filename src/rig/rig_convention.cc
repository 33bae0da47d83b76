#include "rig/rig_convention.h"

#include <algorithm>
#include <cctype>

namespace motionfork {

const std::vector<std::string>& BodyRoles() {
  static const std::vector<std::string> roles = [] {
    std::vector<std::string> r = {"pelvis", "spine", "chest", "neck", "head", "head_end"};
    for (const char* side : {"left_", "right_"}) {
      for (const char* joint :
           {"clavicle", "shoulder", "elbow", "wrist", "hip", "knee", "ankle", "toe"}) {
        r.push_back(std::string(side) + joint);
      }
    }
    r.push_back("root");
    return r;
  }();
  return roles;
}

bool IsBodyRole(std::string_view role) {
  const auto& roles = BodyRoles();
  return std::find(roles.begin(), roles.end(), role) != roles.end();
}

const std::vector<std::pair<std::string, double>>& DerivedRole(const std::string& role) {
  static const std::map<std::string, std::vector<std::pair<std::string, double>>> derived = {
      {"pelvis", {{"left_hip", 0.5}, {"right_hip", 0.5}}},
      {"spine", {{"pelvis", 0.5}, {"chest", 0.5}}},
      {"neck", {{"chest", 0.5}, {"head", 0.5}}},
      {"chest", {{"left_shoulder", 0.5}, {"right_shoulder", 0.5}}},
  };
  static const std::vector<std::pair<std::string, double>> none;
  const auto it = derived.find(role);
  return it == derived.end() ? none : it->second;
}

std::string NormalizeJointName(std::string_view name) {
  const size_t colon = name.rfind(':');
  if (colon != std::string_view::npos) name.remove_prefix(colon + 1);
  std::string out;
  out.reserve(name.size());
  for (char c : name) {
    if (c == '_' || c == '-' || c == '.' || c == ' ') continue;
    out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return out;
}

}  // namespace motionfork
