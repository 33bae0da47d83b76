// Posing a BVH rig (io/bvh.h, BvhRig) so that some of its joints land where wanted: the rotations
// of the joints above them solved, everything else held. How futures predicted on a model's
// skeleton are written back on a user's own rig (pipeline/export_on_rig.h).
//
// Joint by joint from the root down, each joint with targeted joints below it turns (its
// rotation channels) so that its nearest targeted descendants -- the first along each path down,
// through joints held as they are -- point at their targets: the shortest turn for one, the
// least-squares turn (Kabsch, weighted by distance) for several. The root is moved (its position
// channels) so that it, or its nearest targeted descendant, lands on its target; a root that is
// not targeted itself keeps its rotation. Bones keep their lengths (rotations only, position
// channels of other joints held), so a target a bone cannot reach is missed by what Miss() says.
#pragma once

#include <cstdint>
#include <vector>

#include "io/bvh.h"

namespace motionfork::pipeline {

class RigSolver {
 public:
  // targeted: [nodes], 1 = the node has a target in every frame solved.
  RigSolver(const BvhRig& rig, std::vector<uint8_t> targeted);

  // values: one frame of rig.num_channels values, the held pose on entry, solved on return
  // (passes of the above until they stop gaining, at most kMaxPasses).
  // targets: [nodes, 3] world positions, file units (read only where targeted).
  void Solve(const std::vector<double>& targets, double* values) const;

  // The largest distance (file units) of a targeted node from its target in frame `values`.
  double Miss(const std::vector<double>& targets, const double* values) const;

 private:
  static constexpr int kMaxPasses = 20;
  void Pass(const std::vector<double>& targets, double* values) const;
  const BvhRig& rig_;
  std::vector<uint8_t> targeted_;
  std::vector<std::vector<int>> nearest_;  // [node] -> its nearest targeted descendants
};

}  // namespace motionfork::pipeline
