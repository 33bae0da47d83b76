// A skeleton config as loaded (config/skeleton_config.h reads configs/skeletons/*.yaml): the
// skeleton of the files users hold, the protocol skeleton made from it, and the joint selection
// between them; and putting a motion read from a file onto it.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/joint_selection.h"
#include "core/motion.h"
#include "core/skeleton.h"

namespace motionfork {

struct SkeletonConfig {
  std::string path;                          // the YAML file it came from
  std::shared_ptr<const Skeleton> source;    // as stored in the dataset's files
  std::shared_ptr<const Skeleton> skeleton;  // the protocol skeleton (source when nothing is cut)
  std::optional<JointSelection> selection;   // source -> skeleton, when joints are cut
};

// Puts a motion read from a file onto a config's skeleton:
// - joints named like the protocol skeleton's (any order): re-ordered onto it;
// - joints named like the source skeleton's (e.g. a Bandai BVH): the config's selection applied;
// - an anonymous skeleton (.npy) with the protocol's or the source's joint count: bound by index
//   (the source then goes through the selection).
// Throws std::invalid_argument saying which joints or counts did not match.
Motion ConformToSkeleton(const Motion& motion, const SkeletonConfig& config);

}  // namespace motionfork
