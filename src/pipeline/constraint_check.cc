#include "pipeline/constraint_check.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"

namespace motionfork::pipeline {
namespace {

// Puts the motion on the set's own skeleton config when it names one and the motion fits it
// (a 22-joint Bandai BVH -> the 17 protocol joints; a 17-joint .npy -> named joints); otherwise
// the set binds to the motion's joint names as they are.
// by_roles: the motion's joints may also map by their roles (rig conventions, its joint map).
ConstraintCheck BindSet(const std::string& path, const Motion& motion, bool skeleton_given,
                        const std::string& config_dir, const LoadedMotion* by_roles) {
  ConstraintCheck b;
  b.path = path;
  b.spec = LoadConstraintConfig(path);
  b.motion = motion;
  if (!skeleton_given && !b.spec.skeleton.empty()) {
    try {
      const SkeletonConfig sc =
          LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", b.spec.skeleton));
      if (by_roles) {
        ConformedMotion c = ConformForModel(motion, {}, sc, by_roles->options, by_roles->read_scale,
                                            by_roles->unit_given);
        b.motion = std::move(c.motion);
        b.notes = std::move(c.notes);
      } else {
        b.motion = ConformToSkeleton(motion, sc);
      }
    } catch (const std::invalid_argument&) {
      // Not that skeleton's joints: bind by the motion's own names below.
    }
  }
  if (b.motion.skeleton().is_anonymous() && b.motion.skeleton().joint_name(0) == "j0") {
    throw std::invalid_argument(
        "the motion's joints have no names (a .npy file) and do not fit "
        "skeleton '" +
        b.spec.skeleton + "' of constraint set '" + b.spec.name + "': pass --skeleton NAME");
  }
  b.set = ConstraintSet::Build(b.spec, b.motion.skeleton());
  return b;
}

ConstraintCheck ChooseSet(const LoadedMotion& lm, const std::string& file,
                          const std::string& constraints, const std::string& config_dir) {
  const Motion& motion = lm.motion;
  const bool skeleton_given = lm.skeleton_config.has_value();
  if (!constraints.empty()) {
    return BindSet(ResolveConfigPath(config_dir, "constraints", constraints), motion,
                   skeleton_given, config_dir, &lm);
  }
  if (skeleton_given) {
    // The shipped set named like the skeleton (bandai, h36m, humaneva), if there is one.
    const std::filesystem::path shipped = std::filesystem::path(config_dir) / "constraints" /
                                          (lm.skeleton_config->skeleton->name() + ".yaml");
    if (std::filesystem::is_regular_file(shipped)) {
      return BindSet(shipped.string(), motion, skeleton_given, config_dir, nullptr);
    }
  }
  // Detect: the shipped sets whose joints the motion has; failing those, the ones its joints map
  // onto by their roles (another rig's names).
  std::vector<ConstraintCheck> fits;
  std::string names;
  for (const LoadedMotion* by_roles : {static_cast<const LoadedMotion*>(nullptr), &lm}) {
    if (!fits.empty()) break;
    names.clear();
    for (const std::string& name : ListConfigs(config_dir, "constraints")) {
      names += (names.empty() ? "" : ", ") + name;
      try {
        fits.push_back(BindSet(ResolveConfigPath(config_dir, "constraints", name), motion,
                               skeleton_given, config_dir, by_roles));
      } catch (const std::exception&) {
        // Does not fit this motion.
      }
    }
  }
  if (fits.size() == 1) return std::move(fits.front());
  std::string which;
  for (const ConstraintCheck& b : fits) which += (which.empty() ? "" : ", ") + b.spec.name;
  throw std::invalid_argument(
      fits.empty() ? "no shipped constraint set (" + names + ") fits the joints of " + file +
                         " (skeleton '" + motion.skeleton().name() +
                         "'): pass --constraints NAME|FILE, or --skeleton NAME"
                   : "several shipped constraint sets fit " + file + " (" + which +
                         "): choose one with --constraints NAME or --skeleton NAME");
}

}  // namespace

ConstraintCheck CheckMotion(const LoadedMotion& loaded, const std::string& file,
                            const std::string& constraints, const std::string& config_dir,
                            int worst) {
  ConstraintCheck c = ChooseSet(loaded, file, constraints, config_dir);
  c.result = Check(*c.set, c.motion);
  c.summary = Summarize(*c.set, c.result, worst);
  return c;
}

std::string AnglesCsv(const ConstraintSet& set, const CheckResult& r, double fps) {
  std::string out = "frame,time_s";
  for (const Constraint& c : set.constraints()) out += "," + c.name;
  out += "\n";
  char buf[32];
  for (int t = 0; t < r.num_frames; ++t) {
    std::snprintf(buf, sizeof(buf), "%d,%.6g", t, t / fps);
    out += buf;
    for (int c = 0; c < r.num_constraints; ++c) {
      out += ',';
      if (r.at(t, c) != AngleStatus::kDegenerate) {
        std::snprintf(buf, sizeof(buf), "%.4f", r.angle(t, c));
        out += buf;
      }
    }
    out += '\n';
  }
  return out;
}

}  // namespace motionfork::pipeline
