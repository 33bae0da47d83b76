#include "pipeline/constraint_listing.h"

#include <stdexcept>

#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "constraints/constraint_set.h"
#include "core/text_format.h"

namespace motionfork::pipeline {

std::string ConstraintSetListing(const std::string& config_dir, const std::string& constraints,
                                 const std::string& skeleton) {
  const std::string path = ResolveConfigPath(config_dir, "constraints", constraints);
  ConstraintLoadOptions load_options;
  load_options.require_ranges = false;
  const ConstraintSetSpec spec = LoadConstraintConfig(path, load_options);
  const std::string skeleton_name = skeleton.empty() ? spec.skeleton : skeleton;
  if (skeleton_name.empty()) {
    throw std::invalid_argument(path + " names no skeleton: pass --skeleton NAME");
  }
  const SkeletonConfig config =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", skeleton_name));
  ConstraintBuildOptions build_options;
  build_options.require_ranges = false;
  std::string text;
  const ConstraintSet set = ConstraintSet::Build(spec, *config.skeleton, build_options);
  StringAppendf(&text,
                "constraint set %s (%s) on skeleton %s: %d angles from %zu definitions, %d vector "
                "operations\n",
                set.name().c_str(), path.c_str(), config.skeleton->name().c_str(),
                set.num_constraints(), spec.constraints.size(), set.num_registers());
  for (const Constraint& c : set.constraints()) {
    if (c.has_range) {
      StringAppendf(&text, "\n%s  [%g, %g] deg\n", c.name.c_str(), c.lower_deg, c.upper_deg);
    } else {
      StringAppendf(&text, "\n%s  (no range yet)\n", c.name.c_str());
    }
    StringAppendf(&text, "  a = %s\n  b = %s\n", c.a_text.c_str(), c.b_text.c_str());
  }
  return text;
}

}  // namespace motionfork::pipeline
