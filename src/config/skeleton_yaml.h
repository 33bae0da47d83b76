// A skeleton spec inside a bundle's YAML (`skeleton:` mapping: name, joints [name, parent],
// left_right pairs, partitions as joint lists). Used by config and the bundle layer.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "core/skeleton.h"

namespace motionfork {

// Reads root["skeleton"]; FormatError naming the file when it is missing or mistyped.
SkeletonSpec ParseSkeletonSpec(const std::string& path, const YAML::Node& root);
// Writes `skeleton: {...}` into an open mapping.
void EmitSkeletonSpec(YAML::Emitter& out, const SkeletonSpec& spec);

}  // namespace motionfork
