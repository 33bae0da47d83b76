// Body parts as the generator sees them: graph nodes (joints without the root, node = joint - 1)
// per part, in prediction order, from a skeleton partition; and which parts a request fixes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/skeleton.h"

namespace motionfork {

struct PartPlan {
  std::string partition;                    // partition name in the skeleton
  std::vector<std::string> names;           // part names, prediction order
  std::vector<std::vector<int64_t>> nodes;  // graph nodes of each part

  int num_parts() const { return static_cast<int>(names.size()); }
  // Index of a part by name; throws std::invalid_argument listing the known parts.
  int Index(const std::string& part) const;
  // One flag per part: true for the parts named in `fixed` (each must exist, no repeats).
  std::vector<bool> FixedMask(const std::vector<std::string>& fixed) const;
};

// partition "" = the skeleton's first (default) partition.
PartPlan MakePartPlan(const Skeleton& skeleton, const std::string& partition = "");

}  // namespace motionfork
