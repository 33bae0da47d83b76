// Joint selection: keep a named subset of a skeleton's joints, in a given order.
//
// A kept joint's parent is its nearest kept ancestor in the source skeleton, unless an explicit
// re-parenting names another kept joint (Human3.6M's published 17-joint skeleton hangs both
// shoulders on the thorax although the nearest kept ancestor is the spine).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/motion.h"
#include "core/skeleton.h"

namespace motionfork {

struct JointSelectionSpec {
  std::string name;                             // name of the resulting skeleton
  std::vector<std::string> keep;                // source joint names, in the new order (root first)
  std::map<std::string, std::string> reparent;  // kept joint -> kept parent overriding the default
  std::vector<std::pair<std::string, std::string>> left_right;  // pairs in the new skeleton
  std::vector<PartitionSpec> partitions;                        // parts in the new skeleton
};

struct JointSelection {
  Skeleton skeleton;              // the new skeleton
  std::vector<int> source_index;  // new joint j = source joint source_index[j]
};

// Throws std::invalid_argument naming the unknown joint, a duplicate, or an order in which a
// joint would come before its parent.
JointSelection SelectJoints(const Skeleton& source, const JointSelectionSpec& spec);

// Re-maps a motion whose skeleton has the source joints (matched by name, so a motion from any
// file with those joint names works). Throws when a kept joint is missing from the motion.
Motion ApplySelection(const Motion& motion, const JointSelection& selection);

}  // namespace motionfork
