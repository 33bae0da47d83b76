// Checking poses against a ConstraintSet: per frame and per constraint the angle, and whether it
// is inside its range, below it, above it, or undefined (degenerate vectors). No LibTorch.
//
// An angle is undefined when one of its vectors is (near) zero: a bone shorter than
// min_bone_length, or a normal of two (near) collinear vectors (sine of their angle below
// min_normal_sine), or a normal built on an undefined vector. Undefined angles are reported as
// AngleStatus::kDegenerate with angle kUndefinedAngle, never as NaN.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "constraints/constraint_set.h"
#include "core/motion.h"

namespace motionfork {

enum class AngleStatus : uint8_t { kInside = 0, kBelow = 1, kAbove = 2, kDegenerate = 3 };
const char* ToString(AngleStatus status);
inline bool IsViolation(AngleStatus s) {
  return s == AngleStatus::kBelow || s == AngleStatus::kAbove;
}

// The angle written for kDegenerate entries (degrees); no real angle is negative.
constexpr float kUndefinedAngle = -1.0f;

struct DegeneracyOptions {
  // A bone shorter than this is undefined (metres). Zero-length bones come from joints placed on
  // top of each other.
  float min_bone_length = 1e-6f;
  // A normal(u, v) is undefined when |u x v| < min_normal_sine * |u| |v|, i.e. the two vectors
  // are within asin(min_normal_sine) of collinear (1e-4: 0.006 degrees). Scale-free.
  float min_normal_sine = 1e-4f;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const DegeneracyOptions& options);

// The checking job. Holds the set by reference (it must outlive the checker) and per-constraint
// bounds; Run() is const and thread-safe (scratch lives on the caller's stack/heap per call).
class AngleChecker {
 public:
  explicit AngleChecker(const ConstraintSet& set, const DegeneracyOptions& options = {});

  const ConstraintSet& set() const { return set_; }

  // positions: [num_frames, J, 3] metres, J = set.num_joints(). Outputs (caller-owned):
  // angles_deg: [num_frames, C] degrees in [0, 180] or kUndefinedAngle; status: [num_frames, C].
  // Either output may be null.
  void Run(const float* positions, int num_frames, float* angles_deg, AngleStatus* status) const;

 private:
  const ConstraintSet& set_;
  DegeneracyOptions options_;
};

// Whole-motion convenience: [T, C] angles and statuses.
struct CheckResult {
  int num_frames = 0;
  int num_constraints = 0;
  std::vector<float> angles_deg;    // [T, C] degrees or kUndefinedAngle
  std::vector<AngleStatus> status;  // [T, C]
  float angle(int t, int c) const {
    return angles_deg[static_cast<size_t>(t) * num_constraints + c];
  }
  AngleStatus at(int t, int c) const {
    return status[static_cast<size_t>(t) * num_constraints + c];
  }
};

// Throws std::invalid_argument when the motion's joint count differs from the set's.
CheckResult Check(const ConstraintSet& set, const Motion& motion,
                  const DegeneracyOptions& options = {});

// Per-constraint figures over the checked frames.
struct ConstraintSummary {
  long long below = 0, above = 0, degenerate = 0;
  long long violations() const { return below + above; }
  double violation_rate = 0;       // violations / frames
  float min_deg = 0, max_deg = 0;  // over defined angles (0, 0 when none)
  int worst_frame = -1;            // frame furthest outside the range, -1 when never violated
  float worst_excess_deg = 0;      // degrees outside the range at worst_frame
};

struct FrameViolation {
  int frame = 0;
  float excess_deg = 0;          // sum over violated constraints of degrees outside the range
  std::vector<int> constraints;  // the constraints violated in that frame
};

struct CheckSummary {
  int frames = 0;
  int valid_frames = 0;       // every angle defined and inside its range
  int violating_frames = 0;   // at least one angle outside its range
  int degenerate_frames = 0;  // at least one angle undefined
  double valid_frame_share() const { return frames ? double(valid_frames) / frames : 1.0; }
  std::vector<ConstraintSummary> constraints;  // [C]
  std::vector<FrameViolation>
      worst_frames;  // violating frames, largest excess first (<= max_worst)
};

// Degrees an angle lies outside [lower, upper] (0 inside).
float ExcessDegrees(const Constraint& c, float angle_deg);

CheckSummary Summarize(const ConstraintSet& set, const CheckResult& result, int max_worst = 5);

}  // namespace motionfork
