#include "config/skeleton_config.h"

#include "config/yaml_util.h"

namespace motionfork {

using yaml_util::Fail;
using yaml_util::StringList;

namespace {

std::vector<std::pair<std::string, std::string>> ReadPairs(const std::string& file,
                                                           const YAML::Node& n) {
  std::vector<std::pair<std::string, std::string>> out;
  if (!n) return out;
  if (!n.IsSequence()) Fail(file, n, "'left_right' must be a list of [left, right] pairs");
  for (const YAML::Node& p : n) {
    if (!p.IsSequence() || p.size() != 2) Fail(file, p, "expected a [left, right] pair");
    out.emplace_back(p[0].as<std::string>(), p[1].as<std::string>());
  }
  return out;
}

std::vector<PartitionSpec> ReadPartitions(const std::string& file, const YAML::Node& n) {
  std::vector<PartitionSpec> out;
  if (!n) return out;
  if (!n.IsSequence()) Fail(file, n, "'partitions' must be a list of {name, parts}");
  for (const YAML::Node& pn : n) {
    PartitionSpec spec;
    spec.name = yaml_util::Get<std::string>(file, pn, "name");
    const YAML::Node parts = pn["parts"];
    if (!parts || !parts.IsSequence() || parts.size() == 0) {
      Fail(file, pn, "partition '" + spec.name + "' needs a non-empty list 'parts'");
    }
    for (const YAML::Node& part : parts) {
      PartSpec ps;
      ps.name = yaml_util::Get<std::string>(file, part, "name");
      ps.joints = StringList(file, part["joints"], "joints");
      ps.subtrees = StringList(file, part["subtrees"], "subtrees");
      ps.rest = yaml_util::GetOr<bool>(file, part, "rest", false);
      if (ps.joints.empty() && ps.subtrees.empty() && !ps.rest) {
        Fail(file, part, "part '" + ps.name + "' needs 'joints', 'subtrees' or 'rest: true'");
      }
      spec.parts.push_back(std::move(ps));
    }
    out.push_back(std::move(spec));
  }
  return out;
}

SkeletonSpec ReadJoints(const std::string& file, const YAML::Node& n, const std::string& name) {
  SkeletonSpec spec;
  spec.name = name;
  if (!n || !n.IsSequence() || n.size() == 0) Fail(file, n, "expected a non-empty list 'joints'");
  for (const YAML::Node& j : n) {
    if (!j.IsSequence() || j.size() != 2) {
      Fail(file, j, "each joint must be [name, parent] (parent ~ for the root)");
    }
    spec.joint_names.push_back(j[0].as<std::string>());
    spec.parent_names.push_back(j[1].IsNull() ? "" : j[1].as<std::string>());
  }
  return spec;
}

}  // namespace

SkeletonConfig LoadSkeletonConfig(const std::string& path) {
  const YAML::Node root = yaml_util::LoadFile(path);
  const std::string name = yaml_util::Get<std::string>(path, root, "name");
  return yaml_util::WithFormatErrors(path, [&] {
    SkeletonConfig out;
    out.path = path;
    const YAML::Node source = root["source"];
    const auto pairs = ReadPairs(path, root["left_right"]);
    const auto partitions = ReadPartitions(path, root["partitions"]);
    if (source) {
      const std::string source_name =
          yaml_util::GetOr<std::string>(path, source, "name", name + "_source");
      out.source = std::make_shared<const Skeleton>(
          Skeleton::Build(ReadJoints(path, source["joints"], source_name)));
      JointSelectionSpec sel;
      sel.name = name;
      sel.keep = StringList(path, root["keep"], "keep");
      if (sel.keep.empty()) sel.keep = out.source->joint_names();
      if (const YAML::Node rep = root["reparent"]) {
        if (!rep.IsMap()) Fail(path, rep, "'reparent' must map joint -> new parent");
        for (const auto& kv : rep)
          sel.reparent[kv.first.as<std::string>()] = kv.second.as<std::string>();
      }
      sel.left_right = pairs;
      sel.partitions = partitions;
      out.selection = SelectJoints(*out.source, sel);
      out.skeleton = std::make_shared<const Skeleton>(out.selection->skeleton);
    } else {
      SkeletonSpec spec = ReadJoints(path, root["joints"], name);
      spec.left_right = pairs;
      spec.partitions = partitions;
      out.skeleton = std::make_shared<const Skeleton>(Skeleton::Build(spec));
      out.source = out.skeleton;
    }
    return out;
  });
}

}  // namespace motionfork
