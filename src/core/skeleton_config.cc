#include "core/skeleton_config.h"

#include <stdexcept>

namespace motionfork {

Motion ConformToSkeleton(const Motion& motion, const SkeletonConfig& config) {
  const Skeleton& have = motion.skeleton();
  auto has_all = [&have](const Skeleton& want) {
    for (const std::string& n : want.joint_names()) {
      if (!have.Find(n)) return false;
    }
    return true;
  };
  // By names: the protocol's joints in any order, or the source's (then selected).
  if (has_all(*config.skeleton))
    return ApplySelection(motion, JointSelection{*config.skeleton, {}});
  if (config.selection && has_all(*config.source)) return ApplySelection(motion, *config.selection);
  // By count, for files that store no names.
  if (have.is_anonymous() && have.joint_name(0) == "j0") {
    if (have.num_joints() == config.skeleton->num_joints()) {
      return Motion(config.skeleton, motion.fps(), motion.positions());
    }
    if (have.num_joints() == config.source->num_joints()) {
      Motion source(config.source, motion.fps(), motion.positions());
      return config.selection ? ApplySelection(source, *config.selection) : source;
    }
    throw std::invalid_argument(
        "a motion with " + std::to_string(have.num_joints()) +
        " unnamed joints does not fit skeleton '" + config.skeleton->name() + "' (expected " +
        std::to_string(config.skeleton->num_joints()) + " or, before joint selection, " +
        std::to_string(config.source->num_joints()) + " joints)");
  }
  std::string list;
  for (const std::string& n : config.skeleton->joint_names()) {
    if (!have.Find(n)) list += (list.empty() ? "" : ", ") + n;
  }
  throw std::invalid_argument("motion with skeleton '" + have.name() + "' lacks joints of '" +
                              config.skeleton->name() + "': " + list);
}

}  // namespace motionfork
