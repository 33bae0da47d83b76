// Constraint configs (configs/constraints/*.yaml) <-> ConstraintSetSpec. The format is
// documented in configs/constraints/README.md.
//
// Parsing checks everything that needs no skeleton: keys, ranges (degrees, 0 <= lower <= upper
// <= 180), expression syntax (bone(a, b), normal(u, v), named vectors), placeholders ({side},
// {other}) and duplicate names. Joint names are checked when the spec is bound to a skeleton
// (ConstraintSet::Build). Every error is a FormatError naming the file, the line, the constraint
// and the problem.
#pragma once

#include <string>

#include "constraints/constraint_spec.h"

namespace motionfork {

struct ConstraintLoadOptions {
  // false: constraints may omit 'range' (a definitions file about to be fitted). Constraints
  // without a range get has_range = false and [0, 180].
  bool require_ranges = true;
};

ConstraintSetSpec LoadConstraintConfig(const std::string& path,
                                       const ConstraintLoadOptions& options = {});

// Same from YAML text; source_name names it in error messages.
ConstraintSetSpec ParseConstraintConfig(const std::string& yaml_text,
                                        const std::string& source_name,
                                        const ConstraintLoadOptions& options = {});

// Parses one vector expression ("normal(bone(Hips, LHip), bone(LHip, LKnee))"). Throws
// std::invalid_argument saying what was expected where (column) when the text is malformed.
// Named vectors are not resolved here (a bare name is an error).
VectorExpr ParseVectorExpression(const std::string& text);

// The spec as YAML text, definitions as written (a_text/b_text, named vectors) and the current
// ranges; header_comment lines (without '#') go first. Parsing the result gives the same spec.
std::string FormatConstraintConfig(const ConstraintSetSpec& spec,
                                   const std::string& header_comment);

}  // namespace motionfork
