// Rig conventions and joint maps (configs/rigs/*.yaml, a user's --joint-map FILE) -> RigConvention
// (rig/rig_convention.h). The format is documented in configs/rigs/README.md.
#pragma once

#include <string>
#include <vector>

#include "core/skeleton.h"
#include "rig/rig_convention.h"

namespace motionfork {

// Throws FormatError naming the file and line: an unknown role (listing the roles), a blend whose
// weights do not match its joints or do not sum to 1, a joint given no name.
RigConvention LoadRigConvention(const std::string& path);

// Every shipped convention (config_dir/rigs/*.yaml), sorted by name; empty when the folder is
// absent.
std::vector<RigConvention> LoadRigConventions(const std::string& config_dir);

// The skeleton's ankles: the joints the shipped convention that names its joints gives the roles
// left_ankle and right_ankle (indices, in joint order); empty when no convention names it.
std::vector<int> AnkleJoints(const Skeleton& skeleton, const std::string& config_dir);

}  // namespace motionfork
