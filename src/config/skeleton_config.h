// Skeleton configs (configs/skeletons/*.yaml) -> skeletons.
//
// A config describes the skeleton of the files users hold ("source": joints with parents, in file
// order) and, optionally, the protocol skeleton made from it by keeping named joints ("keep",
// "reparent"); left/right pairs and body-part partitions refer to the protocol skeleton's names.
// See configs/skeletons/README.md for the documented format.
#pragma once

#include <string>

#include "core/skeleton_config.h"

namespace motionfork {

// Throws FormatError naming the file and line for YAML problems and the offending joint for
// structural ones (unknown parent, parent after child, overlapping parts, ...).
SkeletonConfig LoadSkeletonConfig(const std::string& path);

}  // namespace motionfork
