// PoseValidator: is a motion plausible? Two optional judges:
//   - angle ranges (a constraint set): a frame is a violation when any constraint is outside;
//   - the pose prior (a normalizing flow): negative log-likelihood per pose, nats.
// A model bundle carries both (DIR/constraints.yaml, DIR/prior/) when it was trained with them;
// AttachToBundle puts them there. No LibTorch in this header.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/skeleton.h"
#include "io/prediction_file.h"

namespace motionfork {

class ConstraintSet;
class AngleChecker;
class PosePrior;

class PoseValidator {
 public:
  // constraints_yaml / prior_dir may be "" (that judge is off). Throws FormatError naming the file
  // when one does not load or does not fit the skeleton.
  PoseValidator(std::shared_ptr<const Skeleton> skeleton, double fps,
                const std::string& constraints_yaml, const std::string& prior_dir);
  // From a model bundle: DIR/constraints.yaml and DIR/prior/ when present.
  static PoseValidator FromBundle(const std::string& bundle_dir,
                                  std::shared_ptr<const Skeleton> skeleton, double fps);
  ~PoseValidator();
  PoseValidator(PoseValidator&&) noexcept;
  PoseValidator& operator=(PoseValidator&&) noexcept;

  bool has_constraints() const;
  bool has_prior() const;
  // "angles: PATH; prior: DIR" (what is on), or "" when nothing is.
  const std::string& described() const { return described_; }

  // positions [frames, J, 3] metres on the skeleton. Per frame: 1 when an angle range is violated.
  std::vector<double> ViolationFlags(const float* positions, int frames) const;
  // Per frame: the prior's negative log-likelihood of the pose.
  std::vector<double> PriorNll(const float* positions, int frames) const;
  // Names of the constraints violated in some frame, in the set's order (empty without a set).
  std::vector<std::string> ViolatedConstraints(const float* positions, int frames) const;
  // The prior's bound on a motion's mean NLL: the 99th percentile of its held-out real poses'
  // NLL, from its training summary; nothing without a prior or when the summary lacks it.
  std::optional<double> prior_bound() const;
  // The prior's typical bone lengths ([J-1] metres, bone k ends at joint k + 1); empty without.
  const std::vector<double>& reference_bone_lengths() const;
  // Whole-motion summary: violating frames, mean prior NLL when a prior is on, prior_ok = that
  // mean within prior_bound(), valid = both.
  SampleValidity Score(const float* positions, int frames) const;

 private:
  std::shared_ptr<const Skeleton> skeleton_;
  double fps_ = 0;
  std::unique_ptr<ConstraintSet> set_;
  std::unique_ptr<AngleChecker> checker_;
  std::unique_ptr<PosePrior> prior_;
  std::string described_;
};

// Copies a constraint config (as DIR/constraints.yaml) and a prior bundle (as DIR/prior/) into a
// model bundle so that it describes itself; "" skips one. Each file is written all-or-nothing.
void AttachToBundle(const std::string& bundle_dir, const std::string& constraints_yaml,
                    const std::string& prior_dir);

}  // namespace motionfork
