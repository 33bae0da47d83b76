// Skeleton: an immutable description of a kinematic tree.
//
// Joints are stored flat, root first and every parent before its children (depth-first order is
// not required, only parent-before-child), so one pass over the joints is enough for forward
// kinematics. A skeleton also carries its left/right joint pairs and named partitions into body
// parts (e.g. "default" = legs then upper body), which later modules use for mirroring and for
// part-wise prediction. Build one with Skeleton::Build (by names) or Skeleton::FromParents (by
// indices); both validate and throw std::invalid_argument with a message naming the joint.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace motionfork {

// One body part: a name and the joints (indices into the skeleton) it owns.
struct BodyPart {
  std::string name;
  std::vector<int> joints;
};

// An ordered split of all non-root joints into disjoint parts (order = prediction order).
struct Partition {
  std::string name;
  std::vector<BodyPart> parts;
};

// By-name description of a skeleton, as written in YAML configs.
struct PartSpec {
  std::string name;
  std::vector<std::string> joints;    // listed joints
  std::vector<std::string> subtrees;  // every joint in the subtree rooted at each of these
  bool rest = false;                  // every non-root joint no other part of the partition owns
};
struct PartitionSpec {
  std::string name;
  std::vector<PartSpec> parts;
};
struct SkeletonSpec {
  std::string name;
  std::vector<std::string> joint_names;
  std::vector<std::string> parent_names;  // "" for the root; same length as joint_names
  std::vector<std::pair<std::string, std::string>> left_right;  // (left, right) joint names
  std::vector<PartitionSpec> partitions;
};

class Skeleton {
 public:
  // Validates and builds. Throws std::invalid_argument naming the offending joint or part.
  static Skeleton Build(const SkeletonSpec& spec);
  // Index form: parents[j] < j for j > 0, parents[0] == -1. Pairs and partitions may be empty.
  static Skeleton FromParents(std::string name, std::vector<std::string> joint_names,
                              std::vector<int> parents,
                              std::vector<std::pair<int, int>> left_right = {},
                              std::vector<Partition> partitions = {});
  // A skeleton for bare arrays whose joints have no names: joints "j0".."j{n-1}", all children of
  // j0. Used only to describe files read without a skeleton; its limb structure means nothing.
  static Skeleton Anonymous(int num_joints);
  // Named joints whose tree is unknown (e.g. from a CSV header): all children of the first joint,
  // is_anonymous() true. Map it onto a real skeleton by names (ConformToSkeleton).
  static Skeleton Unlinked(std::string name, std::vector<std::string> joint_names);

  const std::string& name() const { return name_; }
  int num_joints() const { return static_cast<int>(names_.size()); }
  const std::vector<std::string>& joint_names() const { return names_; }
  const std::string& joint_name(int j) const { return names_.at(j); }
  const std::vector<int>& parents() const { return parents_; }
  int parent(int j) const { return parents_.at(j); }
  // True when the parents are unknown (Anonymous, Unlinked): limbs mean nothing.
  bool is_anonymous() const { return anonymous_; }

  // Index of a joint, or nullopt.
  std::optional<int> Find(std::string_view joint_name) const;
  // Index of a joint; throws std::invalid_argument listing the known names when absent.
  int Index(std::string_view joint_name) const;

  const std::vector<std::pair<int, int>>& left_right_pairs() const { return left_right_; }
  // The joint's mirror partner, or the joint itself when it is unpaired (spine, head).
  int Mirror(int j) const { return mirror_.at(j); }

  // Joints of the subtree rooted at j (j included), in skeleton order.
  std::vector<int> Subtree(int j) const;

  const std::vector<Partition>& partitions() const { return partitions_; }
  // Partition by name ("" = the first, i.e. the default); throws when absent.
  const Partition& GetPartition(std::string_view partition_name = "") const;

  // The by-name description that Build() turns back into this skeleton (parts as joint lists).
  SkeletonSpec ToSpec() const;

  // Same names and parents (pairs and partitions are not compared).
  bool SameStructure(const Skeleton& other) const;

 private:
  Skeleton() = default;
  void Validate() const;

  std::string name_;
  std::vector<std::string> names_;
  std::vector<int> parents_;
  std::vector<std::pair<int, int>> left_right_;
  std::vector<int> mirror_;
  std::vector<Partition> partitions_;
  bool anonymous_ = false;
};

// Resolves a by-name partition against a skeleton (subtrees and "rest" expanded).
Partition ResolvePartition(const Skeleton& skeleton, const PartitionSpec& spec);

}  // namespace motionfork
