// ConstraintSet: angle-range constraints bound to one skeleton's joint indices and compiled into
// a small program, so checking a frame is a straight loop without lookups or allocation.
//
// Immutable once built (the "model"); share it across threads. Checking lives in checker.h, the
// differentiable penalty in torch/angle_penalty.h, range fitting in fit.h.
//
// Program: a list of vector operations in evaluation order. Operation k writes register k:
//   kBone:  position[to] - position[from]       (joints)
//   kCross: register[x] x register[y]            (earlier registers)
// Identical operations are shared (the torso normal used by five angles is computed once).
// Constraint c is the angle between registers a and b, valid inside [lower_deg, upper_deg].
#pragma once

#include <string>
#include <vector>

#include "constraints/constraint_spec.h"
#include "core/skeleton.h"

namespace motionfork {

enum class Side { kNone, kLeft, kRight };
const char* ToString(Side side);

struct VectorOp {
  enum class Kind { kBone, kCross };
  Kind kind = Kind::kBone;
  int x = 0;  // kBone: from joint; kCross: left operand register
  int y = 0;  // kBone: to joint; kCross: right operand register
};

struct Constraint {
  std::string name;       // "Leg2ThighPlane_L" for a per-side instance, else the spec's name
  std::string base_name;  // the spec's name ("Leg2ThighPlane")
  Side side = Side::kNone;
  int spec_index = 0;    // index into spec().constraints
  int mirror = 0;        // index of the other side's instance (itself when not per-side)
  double lower_deg = 0;  // degrees
  double upper_deg = 180;
  bool has_range = true;
  int a = 0, b = 0;            // registers
  std::string a_text, b_text;  // the vectors with joint names resolved, e.g. "bone(LKnee, LFoot)"
};

struct ConstraintBuildOptions {
  // false: accept constraints without a range (fitting); they get [0, 180], has_range = false.
  bool require_ranges = true;
};

class ConstraintSet {
 public:
  // Binds names to the skeleton's joints, expands per-side constraints and compiles. When the
  // skeleton declares left/right pairs, checks that each right-side instance is the mirror image
  // of the left one. Throws FormatError naming spec.source, the constraint and the problem
  // (unknown joint with the known names, missing range, a vector that is zero by construction,
  // a right instance that is not the mirror of the left).
  static ConstraintSet Build(const ConstraintSetSpec& spec, const Skeleton& skeleton,
                             const ConstraintBuildOptions& options = {});

  const std::string& name() const { return spec_.name; }
  const ConstraintSetSpec& spec() const { return spec_; }
  const std::string& skeleton_name() const { return skeleton_name_; }
  // Joints per frame the checker expects (the skeleton's joint count).
  int num_joints() const { return num_joints_; }
  int num_constraints() const { return static_cast<int>(constraints_.size()); }
  const std::vector<Constraint>& constraints() const { return constraints_; }
  const Constraint& constraint(int c) const { return constraints_.at(c); }
  const std::vector<VectorOp>& ops() const { return ops_; }
  int num_registers() const { return static_cast<int>(ops_.size()); }
  // Index of a constraint by (instance) name, or -1.
  int Find(const std::string& constraint_name) const;

 private:
  ConstraintSet() = default;

  ConstraintSetSpec spec_;
  std::string skeleton_name_;
  int num_joints_ = 0;
  std::vector<Constraint> constraints_;
  std::vector<VectorOp> ops_;
};

// "bone(a, b)" / "normal(u, v)" text of an expression (placeholders left as written).
std::string ToString(const VectorExpr& e);

}  // namespace motionfork
