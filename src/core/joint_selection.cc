#include "core/joint_selection.h"

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace motionfork {

JointSelection SelectJoints(const Skeleton& source, const JointSelectionSpec& spec) {
  const std::string who = "joint selection '" + spec.name + "'";
  if (spec.keep.empty()) throw std::invalid_argument(who + ": expected joints to keep, got none");
  std::vector<int> src(spec.keep.size());
  std::vector<int> new_of_source(source.num_joints(), -1);
  for (size_t k = 0; k < spec.keep.size(); ++k) {
    src[k] = source.Index(spec.keep[k]);
    if (new_of_source[src[k]] >= 0) {
      throw std::invalid_argument(who + ": joint '" + spec.keep[k] + "' is kept twice");
    }
    new_of_source[src[k]] = static_cast<int>(k);
  }
  SkeletonSpec out;
  out.name = spec.name;
  out.joint_names = spec.keep;
  out.parent_names.resize(spec.keep.size());
  for (size_t k = 0; k < spec.keep.size(); ++k) {
    int p = source.parent(src[k]);
    while (p >= 0 && new_of_source[p] < 0) p = source.parent(p);
    out.parent_names[k] = p >= 0 ? source.joint_name(p) : "";
    auto over = spec.reparent.find(spec.keep[k]);
    if (over != spec.reparent.end()) {
      if (new_of_source[source.Index(over->second)] < 0) {
        throw std::invalid_argument(who + ": joint '" + spec.keep[k] + "' is re-parented to '" +
                                    over->second + "', which is not kept");
      }
      out.parent_names[k] = over->second;
    }
  }
  for (const auto& [child, parent] : spec.reparent) {
    if (std::find(spec.keep.begin(), spec.keep.end(), child) == spec.keep.end()) {
      throw std::invalid_argument(who + ": re-parented joint '" + child + "' is not kept");
    }
  }
  for (size_t k = 1; k < spec.keep.size(); ++k) {
    if (out.parent_names[k].empty()) {
      throw std::invalid_argument(who + ": joint '" + spec.keep[k] +
                                  "' has no kept ancestor; the first kept joint must be an "
                                  "ancestor of every other (the root)");
    }
  }
  for (size_t k = 1; k < spec.keep.size(); ++k) {
    const auto parent = std::find(spec.keep.begin(), spec.keep.end(), out.parent_names[k]);
    if (parent - spec.keep.begin() > static_cast<long>(k)) {
      throw std::invalid_argument(who + ": joint '" + spec.keep[k] +
                                  "' is kept before its parent '" + out.parent_names[k] +
                                  "'; list parents before their children");
    }
  }
  out.left_right = spec.left_right;
  out.partitions = spec.partitions;
  return JointSelection{Skeleton::Build(out), std::move(src)};
}

Motion ApplySelection(const Motion& motion, const JointSelection& selection) {
  const Skeleton& from = motion.skeleton();
  const Skeleton& to = selection.skeleton;
  std::vector<int> index(to.num_joints());
  for (int j = 0; j < to.num_joints(); ++j) {
    auto found = from.Find(to.joint_name(j));
    if (!found) {
      throw std::invalid_argument("motion with skeleton '" + from.name() + "' has no joint '" +
                                  to.joint_name(j) + "' required by '" + to.name() + "'");
    }
    index[j] = *found;
  }
  const int T = motion.num_frames(), J = to.num_joints();
  std::vector<float> out(static_cast<size_t>(T) * J * 3);
  for (int t = 0; t < T; ++t) {
    for (int j = 0; j < J; ++j) {
      const float* s = motion.at(t, index[j]);
      float* d = out.data() + (static_cast<size_t>(t) * J + j) * 3;
      d[0] = s[0];
      d[1] = s[1];
      d[2] = s[2];
    }
  }
  return Motion(std::make_shared<const Skeleton>(to), motion.fps(), std::move(out));
}

}  // namespace motionfork
