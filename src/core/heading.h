// Which way a body faces and turning it about the up axis (issue 27): the ground plane, a pose's
// heading and the rotation that brings a window into the body's own frame at one frame and back.
//
// Frames and units: positions in metres, poses [J, 3] root first; `up` names the data's up axis
// (axis 0-2 and its sign, rig/body_frame.h's ParseUpAxis); the ground plane is the other two axes
// (a, b) = GroundAxes(up), and angles turn a towards b.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>

namespace motionfork {

class Skeleton;

struct UpAxis {
  int axis = 1;  // 0 x, 1 y, 2 z
  int sign = 1;  // +1 or -1
};

// Parses an axis name ("y", "+Z", "-x"; case-insensitive). Throws std::invalid_argument naming the
// choices.
UpAxis ParseUp(const std::string& up);

// The two axes of the ground plane (the ones that are not `up`'s). Throws std::invalid_argument
// for an axis outside 0-2 or a sign other than +1 / -1.
std::pair<int, int> GroundAxes(UpAxis up);

// The joints whose line tells a body's heading: a left/right pair, joint indices of a pose.
struct HeadingJoints {
  int left = -1, right = -1;
};

// The skeleton's first left/right pair whose joints both hang on the root (the hips), else its
// first left/right pair (shoulders); none when it names no pair.
std::optional<HeadingJoints> FindHeadingJoints(const Skeleton& skeleton);

// FindHeadingJoints as indices of the root-relative nodes (joint - 1: poses without their root),
// which the generator sees. Throws std::invalid_argument naming the skeleton when it names no
// left/right pair, or when the pair includes the root.
HeadingJoints HeadingNodes(const Skeleton& skeleton);

// The heading of a pose ([J, 3], any translation): the angle in the ground plane of the line from
// the right joint to the left one. NaN when that line is (nearly, under 1 mm) vertical.
double HeadingAngle(const float* pose, HeadingJoints joints, UpAxis up);

// The heading of a window of poses ([T, J, 3]) at frame `at`: that frame's heading, or when it is
// undefined the heading of the frames' summed right-to-left lines, or 0 when that is too. The
// same window turned by any angle about up gets its heading plus that angle.
double WindowHeading(const float* poses, int frames, int joints, int at, HeadingJoints hj,
                     UpAxis up);

// Turns `points` 3-vectors ([points, 3], in place) by `angle` radians about the up axis (a towards
// b); the up coordinate stays.
void RotateAboutUp(float* xyz, size_t points, double angle, UpAxis up);

// Turns a window of poses ([frames, joints, 3], in place: a history, then perhaps its future)
// into the body's frame of its last history frame: by minus the WindowHeading of its first
// `history` frames at frame history - 1. Returns that turn, for what belongs with the window
// (root paths, pseudo futures: RotateAboutUp by it) and to turn its futures back (by minus it).
double TurnToBodyFrame(float* poses, int frames, int joints, int history, HeadingJoints hj,
                       UpAxis up);

}  // namespace motionfork
