#include "config/skeleton_yaml.h"

#include "config/yaml_util.h"

namespace motionfork {

using yaml_util::Fail;
using yaml_util::Get;

SkeletonSpec ParseSkeletonSpec(const std::string& path, const YAML::Node& root) {
  const YAML::Node s = root["skeleton"];
  if (!s) Fail(path, root, "missing mapping 'skeleton'");
  SkeletonSpec spec;
  spec.name = Get<std::string>(path, s, "name");
  for (const YAML::Node& j : s["joints"]) {
    spec.joint_names.push_back(j[0].as<std::string>());
    spec.parent_names.push_back(j[1].IsNull() ? "" : j[1].as<std::string>());
  }
  for (const YAML::Node& lr : s["left_right"]) {
    spec.left_right.emplace_back(lr[0].as<std::string>(), lr[1].as<std::string>());
  }
  for (const YAML::Node& pn : s["partitions"]) {
    PartitionSpec ps{Get<std::string>(path, pn, "name"), {}};
    for (const YAML::Node& part : pn["parts"]) {
      ps.parts.push_back(PartSpec{Get<std::string>(path, part, "name"),
                                  yaml_util::StringList(path, part["joints"], "joints"),
                                  {},
                                  false});
    }
    spec.partitions.push_back(std::move(ps));
  }
  return spec;
}

void EmitSkeletonSpec(YAML::Emitter& out, const SkeletonSpec& spec) {
  out << YAML::Key << "skeleton" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << spec.name;
  out << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  for (size_t j = 0; j < spec.joint_names.size(); ++j) {
    out << YAML::Flow << YAML::BeginSeq << spec.joint_names[j];
    if (spec.parent_names[j].empty()) {
      out << YAML::Null;
    } else {
      out << spec.parent_names[j];
    }
    out << YAML::EndSeq;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "left_right" << YAML::Value << YAML::BeginSeq;
  for (const auto& [l, r] : spec.left_right)
    out << YAML::Flow << YAML::BeginSeq << l << r << YAML::EndSeq;
  out << YAML::EndSeq;
  out << YAML::Key << "partitions" << YAML::Value << YAML::BeginSeq;
  for (const PartitionSpec& p : spec.partitions) {
    out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << p.name;
    out << YAML::Key << "parts" << YAML::Value << YAML::BeginSeq;
    for (const PartSpec& part : p.parts) {
      out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << part.name;
      out << YAML::Key << "joints" << YAML::Value << YAML::Flow << part.joints << YAML::EndMap;
    }
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::EndMap;
}

}  // namespace motionfork
