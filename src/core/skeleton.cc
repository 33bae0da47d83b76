#include "core/skeleton.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <unordered_set>

namespace motionfork {
namespace {

std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i) out += ", ";
    out += names[i];
  }
  return out;
}

}  // namespace

void Skeleton::Validate() const {
  const std::string who = "skeleton '" + name_ + "'";
  if (names_.empty()) throw std::invalid_argument(who + ": expected at least one joint, got 0");
  if (parents_.size() != names_.size()) {
    throw std::invalid_argument(who + ": expected " + std::to_string(names_.size()) +
                                " parent indices, got " + std::to_string(parents_.size()));
  }
  std::unordered_set<std::string> seen;
  for (int j = 0; j < num_joints(); ++j) {
    if (names_[j].empty()) {
      throw std::invalid_argument(who + ": joint " + std::to_string(j) + " has an empty name");
    }
    if (!seen.insert(names_[j]).second) {
      throw std::invalid_argument(who + ": joint name '" + names_[j] + "' appears twice");
    }
    if (j == 0 && parents_[0] != -1) {
      throw std::invalid_argument(who + ": the first joint '" + names_[0] +
                                  "' must be the root (parent -1), got parent " +
                                  std::to_string(parents_[0]));
    }
    if (j > 0 && (parents_[j] < 0 || parents_[j] >= j)) {
      throw std::invalid_argument(who + ": joint '" + names_[j] + "' (index " + std::to_string(j) +
                                  ") must have a parent listed before it (index 0.." +
                                  std::to_string(j - 1) + "), got " + std::to_string(parents_[j]) +
                                  (parents_[j] < 0 ? " (only the first joint may be a root)" : ""));
    }
  }
  std::vector<int> used(names_.size(), 0);
  for (const auto& [l, r] : left_right_) {
    if (l < 0 || r < 0 || l >= num_joints() || r >= num_joints() || l == r) {
      throw std::invalid_argument(who + ": bad left/right pair (" + std::to_string(l) + ", " +
                                  std::to_string(r) + ")");
    }
    for (int j : {l, r}) {
      if (used[j]++) {
        throw std::invalid_argument(who + ": joint '" + names_[j] +
                                    "' is in more than one left/right pair");
      }
    }
  }
  for (const Partition& p : partitions_) {
    std::vector<int> owner(names_.size(), -1);
    for (size_t k = 0; k < p.parts.size(); ++k) {
      const BodyPart& part = p.parts[k];
      if (part.joints.empty()) {
        throw std::invalid_argument(who + ": part '" + part.name + "' of partition '" + p.name +
                                    "' has no joints");
      }
      for (int j : part.joints) {
        if (j <= 0 || j >= num_joints()) {
          throw std::invalid_argument(who + ": part '" + part.name + "' of partition '" + p.name +
                                      "' holds joint index " + std::to_string(j) +
                                      ", expected a non-root joint (1.." +
                                      std::to_string(num_joints() - 1) + ")");
        }
        if (owner[j] >= 0) {
          throw std::invalid_argument(who + ": joint '" + names_[j] + "' is in parts '" +
                                      p.parts[owner[j]].name + "' and '" + part.name +
                                      "' of partition '" + p.name + "'");
        }
        owner[j] = static_cast<int>(k);
      }
    }
    std::vector<std::string> missing;
    for (int j = 1; j < num_joints(); ++j) {
      if (owner[j] < 0) missing.push_back(names_[j]);
    }
    if (!missing.empty()) {
      throw std::invalid_argument(
          who + ": partition '" + p.name +
          "' must cover every non-root joint; missing: " + JoinNames(missing));
    }
  }
}

Skeleton Skeleton::FromParents(std::string name, std::vector<std::string> joint_names,
                               std::vector<int> parents,
                               std::vector<std::pair<int, int>> left_right,
                               std::vector<Partition> partitions) {
  Skeleton s;
  s.name_ = std::move(name);
  s.names_ = std::move(joint_names);
  s.parents_ = std::move(parents);
  s.left_right_ = std::move(left_right);
  s.partitions_ = std::move(partitions);
  s.Validate();
  s.mirror_.resize(s.names_.size());
  for (int j = 0; j < s.num_joints(); ++j) s.mirror_[j] = j;
  for (const auto& [l, r] : s.left_right_) {
    s.mirror_[l] = r;
    s.mirror_[r] = l;
  }
  return s;
}

Skeleton Skeleton::Anonymous(int num_joints) {
  if (num_joints < 1) {
    throw std::invalid_argument("anonymous skeleton: expected at least 1 joint, got " +
                                std::to_string(num_joints));
  }
  std::vector<std::string> names(num_joints);
  for (int j = 0; j < num_joints; ++j) names[j] = "j" + std::to_string(j);
  return Unlinked("anonymous", std::move(names));
}

Skeleton Skeleton::Unlinked(std::string name, std::vector<std::string> joint_names) {
  std::vector<int> parents(joint_names.size(), 0);
  if (!parents.empty()) parents[0] = -1;
  Skeleton s = FromParents(std::move(name), std::move(joint_names), std::move(parents));
  s.anonymous_ = true;
  return s;
}

Skeleton Skeleton::Build(const SkeletonSpec& spec) {
  const std::string who = "skeleton '" + spec.name + "'";
  if (spec.parent_names.size() != spec.joint_names.size()) {
    throw std::invalid_argument(who + ": expected one parent per joint (" +
                                std::to_string(spec.joint_names.size()) + "), got " +
                                std::to_string(spec.parent_names.size()));
  }
  std::vector<int> parents(spec.joint_names.size(), -1);
  for (size_t j = 0; j < spec.joint_names.size(); ++j) {
    const std::string& p = spec.parent_names[j];
    if (p.empty()) continue;
    auto it = std::find(spec.joint_names.begin(), spec.joint_names.end(), p);
    if (it == spec.joint_names.end()) {
      throw std::invalid_argument(who + ": joint '" + spec.joint_names[j] +
                                  "' names an unknown parent '" + p + "'");
    }
    parents[j] = static_cast<int>(it - spec.joint_names.begin());
  }
  // Pairs and partitions need name lookup: build a bare skeleton first.
  Skeleton bare = FromParents(spec.name, spec.joint_names, parents);
  std::vector<std::pair<int, int>> pairs;
  for (const auto& [l, r] : spec.left_right) pairs.emplace_back(bare.Index(l), bare.Index(r));
  std::vector<Partition> partitions;
  for (const PartitionSpec& ps : spec.partitions) partitions.push_back(ResolvePartition(bare, ps));
  return FromParents(spec.name, spec.joint_names, std::move(parents), std::move(pairs),
                     std::move(partitions));
}

std::optional<int> Skeleton::Find(std::string_view joint_name) const {
  for (int j = 0; j < num_joints(); ++j) {
    if (names_[j] == joint_name) return j;
  }
  return std::nullopt;
}

int Skeleton::Index(std::string_view joint_name) const {
  if (auto j = Find(joint_name)) return *j;
  throw std::invalid_argument("skeleton '" + name_ + "' has no joint '" + std::string(joint_name) +
                              "'; its joints are: " + JoinNames(names_));
}

std::vector<int> Skeleton::Subtree(int j) const {
  std::vector<char> in(names_.size(), 0);
  std::vector<int> out;
  in.at(j) = 1;
  for (int k = 0; k < num_joints(); ++k) {
    if (k == j || (parents_[k] >= 0 && in[parents_[k]])) {
      in[k] = 1;
      out.push_back(k);
    }
  }
  return out;
}

const Partition& Skeleton::GetPartition(std::string_view partition_name) const {
  if (partitions_.empty()) {
    throw std::invalid_argument("skeleton '" + name_ + "' defines no body-part partitions");
  }
  if (partition_name.empty()) return partitions_.front();
  std::vector<std::string> known;
  for (const Partition& p : partitions_) {
    if (p.name == partition_name) return p;
    known.push_back(p.name);
  }
  throw std::invalid_argument("skeleton '" + name_ + "' has no partition '" +
                              std::string(partition_name) + "'; known: " + JoinNames(known));
}

SkeletonSpec Skeleton::ToSpec() const {
  SkeletonSpec spec;
  spec.name = name_;
  spec.joint_names = names_;
  for (int j = 0; j < num_joints(); ++j) spec.parent_names.push_back(j ? names_[parents_[j]] : "");
  for (const auto& [l, r] : left_right_) spec.left_right.emplace_back(names_[l], names_[r]);
  for (const Partition& p : partitions_) {
    PartitionSpec ps{p.name, {}};
    for (const BodyPart& part : p.parts) {
      PartSpec s{part.name, {}, {}, false};
      for (int j : part.joints) s.joints.push_back(names_[j]);
      ps.parts.push_back(std::move(s));
    }
    spec.partitions.push_back(std::move(ps));
  }
  return spec;
}

bool Skeleton::SameStructure(const Skeleton& other) const {
  return names_ == other.names_ && parents_ == other.parents_;
}

Partition ResolvePartition(const Skeleton& skeleton, const PartitionSpec& spec) {
  Partition out;
  out.name = spec.name;
  std::set<int> taken;
  int rest_index = -1;
  for (size_t k = 0; k < spec.parts.size(); ++k) {
    const PartSpec& ps = spec.parts[k];
    BodyPart part;
    part.name = ps.name;
    if (ps.rest) {
      if (rest_index >= 0) {
        throw std::invalid_argument("partition '" + spec.name +
                                    "': only one part may take the rest of the joints");
      }
      rest_index = static_cast<int>(k);
    }
    for (const std::string& n : ps.joints) part.joints.push_back(skeleton.Index(n));
    for (const std::string& n : ps.subtrees) {
      for (int j : skeleton.Subtree(skeleton.Index(n))) part.joints.push_back(j);
    }
    taken.insert(part.joints.begin(), part.joints.end());
    out.parts.push_back(std::move(part));
  }
  if (rest_index >= 0) {
    for (int j = 1; j < skeleton.num_joints(); ++j) {
      if (!taken.count(j)) out.parts[rest_index].joints.push_back(j);
    }
  }
  for (BodyPart& part : out.parts) std::sort(part.joints.begin(), part.joints.end());
  return out;
}

}  // namespace motionfork
