// PoseRepair: the last stage of prediction, driven by the bundle's constraints.yaml.
//  1. Rigid groups (`rigid:`, e.g. Bandai's pelvis): the group's joints are put back on their
//     layout in the history's last frame, turned by the rotation that best fits the prediction
//     (least squares), each with its subtree carried along (bones keep their lengths and turns).
//  2. Angle ranges: a pose that still breaks a range is moved, as little as it takes, back inside
//     every range: gradient steps (Adam) on its joints (not those of rigid groups, placed by
//     step 1) against the angle penalty with ranges narrowed by a margin, held near the
//     prediction and to its bone lengths; each pose stops as soon as it is inside (checked every
//     check_every steps), whatever the other poses of its batch. Poses that break nothing are
//     not touched by this step.
//
// Body parts are repaired one at a time and only their own joints move, so part control holds:
// fixed parts first (against constraints among the root and fixed parts only: identical input
// poses give identical output), then the other parts in prediction order (against constraints
// among the joints decided so far and their own). A constraint or rigid group is handled by each
// part, in that order, whose joints it involves, with the joints decided earlier held where they
// are (a rigid group's rotation is fitted to them when there are any).
#pragma once

#include <torch/torch.h>

#include <memory>
#include <set>
#include <vector>

#include "bodyparts/part_plan.h"
#include "constraints/constraint_set.h"

namespace motionfork {

struct PoseRepairOptions {
  double margin_deg = 0.5;    // target: this far inside each range (bounds of 0 / 180 stay)
  int max_steps = 200;        // Adam steps per part at most
  int check_every = 5;        // each pose stops once it breaks no range (checked this often)
  double step_m = 0.003;      // Adam learning rate, metres
  double angle_weight = 1e4;  // penalty (squared cosine distance past a bound) weight
  double bone_weight = 100;   // squared bone-length change weight (proximity weight is 1)
};

struct PoseRepairStats {
  long long poses = 0;         // poses looked at
  long long repaired = 0;      // poses that broke a range and were moved
  long long still_broken = 0;  // poses that break a range after the repair (max_steps reached)
};

class PoseRepair {
 public:
  // spec: the constraint set with its ranges; skeleton: the model's (root = joint 0); parts: the
  // model's part plan (graph node n = joint n + 1). Throws what ConstraintSet::Build throws.
  PoseRepair(const ConstraintSetSpec& spec, const Skeleton& skeleton, const PartPlan& parts,
             const PoseRepairOptions& options = {});
  ~PoseRepair();
  PoseRepair(PoseRepair&&) noexcept;
  PoseRepair& operator=(PoseRepair&&) noexcept;

  // poses: float [M, J, 3], root at the origin (root-relative), edited in place; templates: the
  // same shape, each pose's reference layout for the rigid groups (its history's last frame, root
  // at the origin); fixed: one flag per part (PartPlan::FixedMask). No autograd needed.
  PoseRepairStats Repair(torch::Tensor& poses, const torch::Tensor& templates,
                         const std::vector<bool>& fixed) const;

 private:
  struct Impl;
  static void RigidStage(const Impl& m, torch::Tensor& poses, const torch::Tensor& templates,
                         const std::set<int>& decided, const std::set<int>& own, bool own_fixed);
  std::unique_ptr<Impl> impl_;
};

}  // namespace motionfork
