// Mapping a motion of one rig onto another skeleton (a model's) by the roles of their joints.
//
// The target's joints get their roles from the convention that names them all (Bandai's,
// Human3.6M's, HumanEva's for the shipped models); the source rig is read with the convention that
// explains most of its joint names and has every role the target needs (or with one forced: a
// user's joint map). A target joint with no counterpart is made as DerivedRole() says (a pelvis
// between the hips); source joints no target joint uses (fingers, toes, twist bones) are listed.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/motion.h"
#include "core/skeleton.h"
#include "rig/rig_convention.h"

namespace motionfork {

struct JointMapping {
  std::string source_rig;  // the convention the source was read with
  std::string target_rig;  // the convention naming the target's joints
  // [target joint] -> (source joint index, weight) pairs, weights summing to 1.
  std::vector<std::vector<std::pair<int, double>>> sources;
  // [target joint] -> where it comes from, for people: "LeftUpLeg", "0.5 LeftUpLeg + 0.5
  // RightUpLeg".
  std::vector<std::string> described;
  std::vector<std::string> ignored;  // source joints no target joint uses, in source order
  int source_joints = 0;
};

// The convention whose single-joint entries name every joint of `skeleton`, with each joint's
// role; throws std::invalid_argument when none does.
struct NamedRoles {
  const RigConvention* convention = nullptr;
  std::vector<std::string> roles;  // [joint] -> role
};
NamedRoles RolesOfSkeleton(const Skeleton& skeleton, const std::vector<RigConvention>& conventions);

// Maps `from`'s joints onto `to`'s (see the top of this file). `forced`: read `from` with this
// convention only (a user's joint map). Throws std::invalid_argument saying which roles the
// closest convention could not find, and how to give a joint map.
JointMapping MapJoints(const Skeleton& from, const Skeleton& to,
                       const std::vector<RigConvention>& conventions,
                       const RigConvention* forced = nullptr);

// [T, J_from, 3] -> [T, J_to, 3]: each target joint the weighted mean of its sources.
Motion ApplyJointMapping(const Motion& motion, const JointMapping& mapping,
                         std::shared_ptr<const Skeleton> to);
// A missing-value mask [T, J_from, 3] -> [T, J_to, 3]: missing when any source value is.
std::vector<uint8_t> ApplyJointMapping(const std::vector<uint8_t>& missing,
                                       const JointMapping& mapping);

}  // namespace motionfork
