// A walk made by the project itself: the built-in history of the demo and of tests that want a
// plausible human motion without dataset files. Forward kinematics of a simple gait model (hip,
// knee, arm swing in the sagittal plane, pelvis height from the lower foot, a slight sway), on the
// joints of the Bandai protocol skeleton (configs/skeletons/bandai.yaml), Y up, metres.
#pragma once

#include <memory>

#include "core/motion.h"

namespace motionfork {

struct DemoWalkOptions {
  int frames = 60;
  double fps = 30;
  double stride_hz = 0.9;  // gait cycles (two steps) per second
  double speed = 1.2;      // metres per second, forward
  double heading_deg = 0;  // walking direction, degrees about +Y from +Z
  double phase = 0;        // radians into the gait cycle at frame 0
};

// The skeleton must hold the Bandai protocol joints by name (Hips, Spine, Chest, Neck, Head,
// UpperLeg/LowerLeg/Foot_L/_R, UpperArm/LowerArm/Hand_L/_R) and no other joints; throws
// std::invalid_argument naming the first joint it lacks or does not know, or a bad option.
Motion MakeDemoWalk(std::shared_ptr<const Skeleton> skeleton, const DemoWalkOptions& options = {});

}  // namespace motionfork
