// Positions -> joint rotations: the rest pose and per-frame local rotations whose forward
// kinematics reproduce a motion of positions on its skeleton (what a BVH file needs).
//
// Rest pose: every bone keeps one length (its mean over the frames) and points along its mean
// direction in its parent joint's frame, so the rest is an average pose and the swings away
// from it stay small (a swing is only ill-defined for a bone pointing opposite its rest).
// Rotations, joint by joint from the root down, fitted to the children whose bones keep their
// length (see BoneLengths):
//   - one such child: the shortest-arc swing from the child's rest direction to its direction in
//     this frame (no twist about the bone relative to the parent);
//   - several (hips, chest): the least-squares rotation of all their rest directions onto theirs
//     (Kabsch, weighted by bone length), the rest shape being their Procrustes mean over frames;
//   - none: the identity (the joint follows its parent; a BVH writer gives a leaf an End Site).
// A child that one rotation cannot place (a branching joint whose children move against each
// other, a bone whose length varies) gets a translation of its own, in the parent's frame.
#pragma once

#include <memory>
#include <vector>

#include "core/motion.h"

namespace motionfork {

enum class BoneLengths {
  // Every bone keeps its mean length: rotations on a fixed skeleton, as animators expect and a
  // predicted future needs (its bones wobble). Positions come back exactly when the input's bones
  // keep their lengths, otherwise as their directions at the mean lengths.
  kMean,
  // A bone whose length varies by more than `tolerance` carries its exact offset as a translation
  // of its own, so every position comes back (format conversion of a skeleton with joints left
  // out, e.g. the protocols' chest -> upper arm over the shoulder, or of a ground-level root the
  // hips walk away from). Such bones do not steer their parent's rotation.
  kExact,
};

struct PoseFitOptions {
  BoneLengths lengths = BoneLengths::kExact;
  // Metres. A child that its parent's rotation puts further than this from where the input has it
  // (at the mean length, in some frame) gets a translation of its own; so does, under kExact, a
  // bone whose length strays further than this from its mean. < 0: never (rotations only).
  double tolerance = 1e-5;
  // A bone shorter than this in some frame has no direction: FitPose throws, naming the frame.
  double min_bone_length = 1e-6;
};

struct PoseFit {
  int num_frames = 0;
  int num_joints = 0;
  // Rest pose (every rotation the identity): each joint's offset from its parent, [J, 3] metres,
  // in the world frame (= every joint's frame at rest). Row 0: the root's position in frame 0.
  std::vector<double> offsets;
  // [J]: true when the joint carries its own translation each frame (always the root).
  std::vector<bool> translated;
  // [T, J, 3] metres: each joint's translation from its parent in the parent's frame (the
  // root's: its world position). Equal to the rest offset for joints that are not translated.
  std::vector<double> translations;
  // [T, J, 9] row-major local rotations: joint frame -> parent frame (the root's: -> world).
  std::vector<double> rotations;

  const double* rotation(int t, int j) const {
    return rotations.data() + 9 * (static_cast<size_t>(t) * num_joints + j);
  }
  const double* translation(int t, int j) const {
    return translations.data() + 3 * (static_cast<size_t>(t) * num_joints + j);
  }
};

// Throws std::invalid_argument when the skeleton has no limb structure (anonymous or unlinked:
// read without a hierarchy), has fewer than 2 joints, when the motion has no frames, or when a
// bone is shorter than min_bone_length (naming the frame and the bone).
PoseFit FitPose(const Motion& motion, const PoseFitOptions& options = {});

// Forward kinematics of a fit: world positions [T, J, 3] metres on the skeleton it was fitted on
// (fit.num_joints joints, parents before children). fps in Hz.
Motion PoseFitPositions(const PoseFit& fit, std::shared_ptr<const Skeleton> skeleton, double fps);

}  // namespace motionfork
