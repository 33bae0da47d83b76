// Angle-range constraints by joint NAME, as written in configs/constraints/*.yaml (format:
// configs/constraints/README.md). Plain data: src/config parses YAML into these structs, and
// ConstraintSet::Build (constraint_set.h) binds them to a skeleton's joint indices.
//
// Header-only on purpose: the config module fills these structs without linking the
// constraints library.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace motionfork {

// A 3D vector computed from joint positions.
struct VectorExpr {
  enum class Kind {
    kBone,    // position(to) - position(from)
    kNormal,  // cross(operands[0], operands[1]); the order fixes the side the normal points to
  };
  Kind kind = Kind::kBone;
  std::string from, to;              // kBone: joint names, possibly holding {side} / {other}
  std::vector<VectorExpr> operands;  // kNormal: exactly two

  static VectorExpr Bone(std::string from_joint, std::string to_joint) {
    VectorExpr e;
    e.kind = Kind::kBone;
    e.from = std::move(from_joint);
    e.to = std::move(to_joint);
    return e;
  }
  static VectorExpr Normal(VectorExpr u, VectorExpr v) {
    VectorExpr e;
    e.kind = Kind::kNormal;
    e.operands = {std::move(u), std::move(v)};
    return e;
  }
};

// One angle between two vectors, in degrees in [0, 180], valid inside [lower_deg, upper_deg].
struct ConstraintSpec {
  std::string name;       // unique in its set; per-side twins get "_<left token>"/"_<right token>"
  bool per_side = false;  // written once, instantiated for the left and the mirrored right side
  VectorExpr a, b;        // named vectors already expanded
  std::string a_text, b_text;  // the expressions as written (kept to write the file back)
  bool has_range = false;      // false only when loaded for fitting
  double lower_deg = 0;        // degrees, 0 <= lower_deg <= upper_deg <= 180
  double upper_deg = 180;
  // A limit from the literature (e.g. the GSPS table) where the definition is the seed's: a
  // fitted range is widened to include it (RangeFitter), so that real motion of a kind the
  // training data lacks (a dance's deep back bend) is not flagged. The checker reads `range`.
  bool has_anatomical = false;
  double anatomical_lower_deg = 0, anatomical_upper_deg = 180;
  std::string note;           // free text kept when the file is written back
  std::string location;       // where it was read ("line 12"), for error messages; may be empty
  std::string range_comment;  // written after the range as a YAML comment (fit statistics)
};

struct ConstraintSetSpec {
  std::string name;
  std::string source;    // file it came from, for error messages ("" = built in code)
  std::string skeleton;  // skeleton config whose joint names it uses; may be empty
  // Substituted for {side} / {other}: the left instance of a per-side constraint reads
  // {side} = left_token, {other} = right_token; the right instance the reverse (and every
  // cross product in it has its operands swapped, so it measures the same anatomical angle on
  // the mirrored body). Constraints that are not per-side read the left instance's values.
  std::string left_token = "L";
  std::string right_token = "R";
  std::vector<std::pair<std::string, std::string>> vectors;  // named vectors (name, text)
  std::vector<ConstraintSpec> constraints;
  // Groups of joints whose layout relative to the root is the same in every frame of the data
  // (e.g. the pelvis: both hips and the spine's base). Not checked as angles: predictions are put
  // back on them (generator/pose_repair.h).
  std::vector<std::vector<std::string>> rigid;
};

}  // namespace motionfork
