#include "pipeline/motion_input_json.h"

#include <nlohmann/json.hpp>

namespace motionfork::pipeline {

using json = nlohmann::ordered_json;

json MotionInfoJson(const std::string& file, const LoadedMotion& loaded, const BoundingBox& box) {
  const Motion& m = loaded.motion;
  const Skeleton& s = m.skeleton();
  return {{"file", file},
          {"skeleton", s.name()},
          {"joints", s.num_joints()},
          {"joint_names", s.joint_names()},
          {"parents", s.parents()},
          {"frames", m.num_frames()},
          {"fps", m.fps()},
          {"fps_assumed", loaded.fps_assumed},
          {"duration_s", m.duration_seconds()},
          {"bbox_min_m", {box.min[0], box.min[1], box.min[2]}},
          {"bbox_max_m", {box.max[0], box.max[1], box.max[2]}}};
}

}  // namespace motionfork::pipeline
