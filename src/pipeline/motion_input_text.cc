#include "pipeline/motion_input_text.h"

#include "core/text_format.h"

namespace motionfork::pipeline {

std::string MotionInfoText(const std::string& file, const LoadedMotion& lm,
                           const BoundingBox& box) {
  const Motion& m = lm.motion;
  const Skeleton& s = m.skeleton();
  std::string text;
  StringAppendf(&text, "file:      %s\n", file.c_str());
  StringAppendf(&text, "skeleton:  %s (%d joints, root %s)\n", s.name().c_str(), s.num_joints(),
                s.joint_name(0).c_str());
  StringAppendf(&text, "joints:   ");
  for (int j = 0; j < s.num_joints(); ++j) {
    StringAppendf(&text, " %s", s.joint_name(j).c_str());
    if (!s.is_anonymous() && j > 0) StringAppendf(&text, "<%s", s.joint_name(s.parent(j)).c_str());
  }
  text += "\n";
  if (!s.partitions().empty()) {
    for (const Partition& p : s.partitions()) {
      StringAppendf(&text, "parts:     %s:", p.name.c_str());
      for (const BodyPart& part : p.parts)
        StringAppendf(&text, " %s(%zu)", part.name.c_str(), part.joints.size());
      text += "\n";
    }
  }
  StringAppendf(&text, "frames:    %s at %.6g Hz%s (%.2f s)\n",
                WithThousands(m.num_frames()).c_str(), m.fps(),
                lm.fps_assumed ? " (assumed: the file stores no rate; pass --fps)" : "",
                m.duration_seconds());
  StringAppendf(&text, "bounding box (m): x [%.3f, %.3f]  y [%.3f, %.3f]  z [%.3f, %.3f]\n",
                box.min[0], box.max[0], box.min[1], box.max[1], box.min[2], box.max[2]);
  StringAppendf(&text, "extent (m):       %.3f x %.3f x %.3f\n", box.max[0] - box.min[0],
                box.max[1] - box.min[1], box.max[2] - box.min[2]);
  return text;
}

}  // namespace motionfork::pipeline
