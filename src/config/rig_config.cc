#include "config/rig_config.h"

#include <cmath>

#include "config/config_paths.h"
#include "config/yaml_util.h"
#include "rig/joint_mapping.h"

namespace motionfork {
namespace {

using yaml_util::Fail;

// A role's entry: a joint name, {blend: [A, B], weights: [...]}, or a list of those (variants,
// most preferred first).
JointBlend ReadBlend(const std::string& file, const YAML::Node& n, const std::string& role) {
  JointBlend b;
  if (n.IsScalar()) {
    b.joints = {n.as<std::string>()};
    b.weights = {1.0};
    if (b.joints[0].empty()) Fail(file, n, "role '" + role + "' is given an empty joint name");
    return b;
  }
  if (!n.IsMap() || !n["blend"]) {
    Fail(file, n,
         "role '" + role +
             "': expected a joint name, a list of names or {blend: [A, B], "
             "weights: [wa, wb]}");
  }
  yaml_util::CheckKeys(file, n, role, {"blend", "weights"});
  b.joints = yaml_util::StringList(file, n["blend"], "blend");
  if (b.joints.empty()) Fail(file, n, "role '" + role + "': 'blend' lists no joints");
  if (n["weights"]) {
    b.weights = yaml_util::Get<std::vector<double>>(file, n, "weights");
    if (b.weights.size() != b.joints.size()) {
      Fail(file, n["weights"],
           "role '" + role + "': expected " + std::to_string(b.joints.size()) +
               " weights (one per blended joint), got " + std::to_string(b.weights.size()));
    }
    double sum = 0;
    for (double w : b.weights) sum += w;
    if (std::abs(sum - 1.0) > 1e-6) {
      Fail(file, n["weights"],
           "role '" + role + "': weights must sum to 1, got " + std::to_string(sum));
    }
  } else {
    b.weights.assign(b.joints.size(), 1.0 / static_cast<double>(b.joints.size()));
  }
  return b;
}

}  // namespace

RigConvention LoadRigConvention(const std::string& path) {
  const YAML::Node root = yaml_util::LoadFile(path);
  return yaml_util::WithFormatErrors(path, [&] {
    yaml_util::CheckKeys(path, root, "rig", {"name", "joints", "also"});
    RigConvention c;
    c.path = path;
    c.name = yaml_util::Get<std::string>(path, root, "name");
    const YAML::Node joints = root["joints"];
    if (!joints || !joints.IsMap() || joints.size() == 0) {
      Fail(path, root, "expected a map 'joints' from roles to joint names");
    }
    for (const auto& kv : joints) {
      const std::string role = kv.first.as<std::string>();
      if (!IsBodyRole(role)) {
        std::string known;
        for (const std::string& r : BodyRoles()) known += (known.empty() ? "" : ", ") + r;
        Fail(path, kv.first, "unknown role '" + role + "'; the roles are: " + known);
      }
      std::vector<JointBlend>& variants = c.roles[role];
      if (kv.second.IsSequence()) {
        for (const YAML::Node& v : kv.second) variants.push_back(ReadBlend(path, v, role));
        if (variants.empty()) Fail(path, kv.second, "role '" + role + "' lists no joints");
      } else {
        variants.push_back(ReadBlend(path, kv.second, role));
      }
    }
    c.also = yaml_util::StringList(path, root["also"], "also");
    return c;
  });
}

std::vector<RigConvention> LoadRigConventions(const std::string& config_dir) {
  std::vector<RigConvention> out;
  for (const std::string& name : ListConfigs(config_dir, "rigs")) {
    out.push_back(LoadRigConvention(ResolveConfigPath(config_dir, "rigs", name)));
  }
  return out;
}

std::vector<int> AnkleJoints(const Skeleton& skeleton, const std::string& config_dir) {
  try {
    const NamedRoles named = RolesOfSkeleton(skeleton, LoadRigConventions(config_dir));
    std::vector<int> feet;
    for (size_t j = 0; j < named.roles.size(); ++j)
      if (named.roles[j] == "left_ankle" || named.roles[j] == "right_ankle")
        feet.push_back(static_cast<int>(j));
    return feet;
  } catch (const std::invalid_argument&) {
    return {};  // no convention names this skeleton
  }
}

}  // namespace motionfork
