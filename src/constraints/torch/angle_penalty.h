// The angle-range penalty for training (GSPS's angle loss), differentiable, in LibTorch.
//
// For every frame and constraint: 0 while the angle is inside its range; past a bound, the
// squared distance in cosine to that bound, (cos(angle) - cos(bound))^2. As in GSPS, a bound is
// applied only where its cosine lies within [-cos_limit, cos_limit] (0.98: bounds between 11.5
// and 168.5 degrees); bounds of 0 and 180 degrees can never be crossed anyway. Angles with a
// degenerate vector (same rule as the checker) contribute 0, with finite (zero) gradients.
//
// The same ConstraintSet drives the checker (checker.h), so both agree on which constraints are
// violated (tests/constraints/penalty_test.cc). Link motionfork_constraints_torch for this file;
// the checker alone does not need LibTorch.
#pragma once

#include <torch/nn/module.h>
#include <torch/nn/pimpl.h>

#include <vector>

#include "constraints/checker.h"
#include "constraints/constraint_set.h"

namespace motionfork {

struct AnglePenaltyOptions {
  // A bound is applied only when |cos(bound)| <= cos_limit. GSPS: 0.98. 1.0 applies every bound.
  double cos_limit = 0.98;
  DegeneracyOptions degeneracy;  // undefined angles are not penalised
  // CPU float/double poses: one hand-written pass per frame for the forward and one for the
  // backward (~15x faster than composed tensor ops; differentiable once). false: composed tensor
  // ops only (any device, twice differentiable). Both give the same values and gradients.
  bool fused_cpu = true;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const AnglePenaltyOptions& options);

class AnglePenaltyImpl : public torch::nn::Module {
 public:
  // Copies what it needs from the set; the set need not outlive the module. The bounds are
  // buffers (they follow .to(device / dtype)); the joint and register indices stay int64 and
  // are moved to the poses' device when needed.
  explicit AnglePenaltyImpl(const ConstraintSet& set, const AnglePenaltyOptions& options = {});

  // poses: [..., J, 3] (e.g. [B, T, J, 3]) metres, floating point. Returns the cosines of the
  // constraint angles, [..., C]; *defined (if given) receives a [..., C] bool mask, false where
  // the angle is undefined (its cosine is then 0). Differentiable.
  torch::Tensor Cosines(const torch::Tensor& poses, torch::Tensor* defined = nullptr) const;

  // [..., C]: per-constraint penalty (squared cosine distance past an applied bound, else 0).
  torch::Tensor PerConstraint(const torch::Tensor& poses) const;
  // The same from composed tensor ops, whatever options.fused_cpu says (the reference).
  torch::Tensor PerConstraintComposed(const torch::Tensor& poses) const;

  // Scalar: PerConstraint summed over constraints and averaged over frames (every leading
  // dimension). GSPS multiplies it by a weight of 100; the weight is the caller's.
  torch::Tensor forward(const torch::Tensor& poses) const;

  int num_constraints() const { return num_constraints_; }
  int num_joints() const { return num_joints_; }
  // [C] bool: whether the lower / upper bound of each constraint is applied (cos_limit).
  torch::Tensor lower_applied() const { return lower_applied_.to(torch::kBool); }
  torch::Tensor upper_applied() const { return upper_applied_.to(torch::kBool); }

 private:
  struct Level {         // registers computed together: crosses of earlier registers
    torch::Tensor x, y;  // [n] positions in the register tensor
  };
  AnglePenaltyOptions options_;
  int num_joints_ = 0;
  int num_constraints_ = 0;
  torch::Tensor bone_from_, bone_to_;  // [n_bones] joints
  std::vector<Level> levels_;
  torch::Tensor a_, b_;                          // [C] positions in the register tensor
  torch::Tensor cos_lower_, cos_upper_;          // [C] cos(lower_deg) >= cos(upper_deg)
  torch::Tensor lower_applied_, upper_applied_;  // [C] 0/1 (floating, to multiply)
  // The fused kernel's program (CPU): ops [R, 3] int64 (kind 0 bone / 1 cross, x, y),
  // constraints [C, 2] int64 (registers a, b), bounds [C, 4] double (cos lower, cos upper,
  // lower applied, upper applied).
  torch::Tensor program_ops_, program_constraints_, program_bounds_;
};
TORCH_MODULE(AnglePenalty);

}  // namespace motionfork
