#include "pipeline/prior_score.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "config/config_paths.h"
#include "config/skeleton_config.h"

namespace motionfork::pipeline {

Motion OnPriorSkeleton(const LoadedMotion& lm, const PosePrior& prior,
                       const std::string& config_dir, std::vector<std::string>* notes) {
  const Motion& m = lm.motion;
  const Skeleton& want = prior.skeleton();
  if (m.skeleton().SameStructure(want)) return m;
  if (m.skeleton().is_anonymous() && m.num_joints() == want.num_joints() &&
      m.skeleton().joint_name(0) == "j0") {
    return Motion(prior.skeleton_ptr(), m.fps(), m.positions());
  }
  std::string by_name;  // why the joints do not map by name
  {
    // Named joints in another order (e.g. a CSV): re-ordered by name.
    SkeletonConfig same;
    same.source = same.skeleton = prior.skeleton_ptr();
    try {
      return ConformToSkeleton(m, same);
    } catch (const std::invalid_argument& e) {
      by_name = e.what();  // other names: try the training skeleton config below
    }
  }
  if (!lm.skeleton_config && !prior.skeleton_config().empty()) {
    std::optional<SkeletonConfig> sc;
    try {
      sc = LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", prior.skeleton_config()));
    } catch (const std::exception&) {
      // Not available here: the skeleton check below says what is expected.
    }
    if (sc && sc->skeleton->SameStructure(want)) {
      try {
        return ConformToSkeleton(m, *sc);
      } catch (const std::invalid_argument&) {
        // Not this skeleton's joints: reported below.
      }
    }
  }
  if (!(m.skeleton().is_anonymous() && m.skeleton().joint_name(0) == "j0") && !lm.skeleton_config) {
    // Another rig's names: by the roles of its joints.
    SkeletonConfig onto;
    onto.source = onto.skeleton = prior.skeleton_ptr();
    MotionInputOptions how = lm.options;
    how.config_dir = config_dir;
    how.target_up = ProtocolUp(config_dir, prior.summary().protocol);
    try {
      ConformedMotion c = ConformForModel(m, {}, onto, how);
      if (notes) *notes = std::move(c.notes);
      return std::move(c.motion);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("the prior expects poses of skeleton '" + want.name() + "' (" +
                                  std::to_string(want.num_joints()) + " joints); " + e.what());
    }
  }
  if (m.skeleton().is_anonymous() && m.skeleton().joint_name(0) != "j0") {
    // Named joints without a tree (CSV): say which names are missing.
    throw std::invalid_argument("the prior expects poses of skeleton '" + want.name() + "' (" +
                                std::to_string(want.num_joints()) + " joints); " + by_name +
                                " (pass --skeleton NAME to map the file onto a skeleton)");
  }
  prior.CheckSkeleton(m.skeleton());
  return m;
}

PriorScore ScorePoses(const PosePrior& prior, const Motion& motion) {
  PriorScore s;
  s.nll = prior.LogProb(motion);
  for (double& v : s.nll) v = -v;
  const int T = static_cast<int>(s.nll.size());
  if (T == 0) throw std::invalid_argument("expected at least 1 frame, got 0");
  std::vector<double> sorted = s.nll;
  std::sort(sorted.begin(), sorted.end());
  for (double v : s.nll) s.mean += v / T;
  s.median = T % 2 ? sorted[T / 2] : 0.5 * (sorted[T / 2 - 1] + sorted[T / 2]);
  s.min = sorted.front();
  s.max = sorted.back();
  s.worst_frame = static_cast<int>(std::max_element(s.nll.begin(), s.nll.end()) - s.nll.begin());
  s.best_frame = static_cast<int>(std::min_element(s.nll.begin(), s.nll.end()) - s.nll.begin());
  s.held_out_q50 = prior.summary().held_out_nll_q50;
  s.held_out_q99 = prior.summary().held_out_nll_q99;
  if (std::isfinite(s.held_out_q99)) {
    s.above_q99 = static_cast<int>(
        std::count_if(s.nll.begin(), s.nll.end(), [&](double v) { return v > s.held_out_q99; }));
  }
  return s;
}

}  // namespace motionfork::pipeline
