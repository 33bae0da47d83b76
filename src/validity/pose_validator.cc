#include "validity/pose_validator.h"

#include <cmath>
#include <filesystem>

#include "bundle/prior_bundle.h"
#include "config/constraint_config.h"
#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "core/motion.h"
#include "flow/pose_prior.h"
#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

PoseValidator::PoseValidator(std::shared_ptr<const Skeleton> skeleton, double fps,
                             const std::string& constraints_yaml, const std::string& prior_dir)
    : skeleton_(std::move(skeleton)), fps_(fps) {
  if (!constraints_yaml.empty()) {
    set_ = std::make_unique<ConstraintSet>(
        ConstraintSet::Build(LoadConstraintConfig(constraints_yaml), *skeleton_));
    checker_ = std::make_unique<AngleChecker>(*set_);
    described_ = "angles: " + constraints_yaml;
  }
  if (!prior_dir.empty()) {
    prior_ = std::make_unique<PosePrior>(LoadPosePrior(prior_dir));
    prior_->CheckSkeleton(*skeleton_);
    described_ += (described_.empty() ? "" : "; ") + std::string("prior: ") + prior_dir;
  }
}

PoseValidator PoseValidator::FromBundle(const std::string& bundle_dir,
                                        std::shared_ptr<const Skeleton> skeleton, double fps) {
  const fs::path dir(bundle_dir);
  const fs::path constraints = dir / "constraints.yaml", prior = dir / "prior";
  return PoseValidator(std::move(skeleton), fps,
                       fs::is_regular_file(constraints) ? constraints.string() : "",
                       fs::is_directory(prior) ? prior.string() : "");
}

PoseValidator::~PoseValidator() = default;
PoseValidator::PoseValidator(PoseValidator&&) noexcept = default;
PoseValidator& PoseValidator::operator=(PoseValidator&&) noexcept = default;

bool PoseValidator::has_constraints() const { return checker_ != nullptr; }
bool PoseValidator::has_prior() const { return prior_ != nullptr; }

std::vector<double> PoseValidator::ViolationFlags(const float* positions, int frames) const {
  std::vector<double> flags(frames, 0.0);
  if (!checker_) return flags;
  const int C = set_->num_constraints();
  std::vector<AngleStatus> status(static_cast<size_t>(frames) * C);
  checker_->Run(positions, frames, nullptr, status.data());
  for (int t = 0; t < frames; ++t) {
    for (int c = 0; c < C && flags[t] == 0.0; ++c)
      flags[t] = IsViolation(status[static_cast<size_t>(t) * C + c]) ? 1.0 : 0.0;
  }
  return flags;
}

std::vector<double> PoseValidator::PriorNll(const float* positions, int frames) const {
  std::vector<double> nll(frames, 0.0);
  if (!prior_) return nll;
  const Motion m(skeleton_, fps_,
                 std::vector<float>(positions, positions + static_cast<size_t>(frames) *
                                                               skeleton_->num_joints() * 3));
  const std::vector<double> lp = prior_->LogProb(m);
  for (int t = 0; t < frames; ++t) nll[t] = -lp[t];
  return nll;
}

std::vector<std::string> PoseValidator::ViolatedConstraints(const float* positions,
                                                            int frames) const {
  std::vector<std::string> names;
  if (!checker_) return names;
  const int C = set_->num_constraints();
  std::vector<AngleStatus> status(static_cast<size_t>(frames) * C);
  checker_->Run(positions, frames, nullptr, status.data());
  for (int c = 0; c < C; ++c) {
    for (int t = 0; t < frames; ++t) {
      if (IsViolation(status[static_cast<size_t>(t) * C + c])) {
        names.push_back(set_->constraint(c).name);
        break;
      }
    }
  }
  return names;
}

std::optional<double> PoseValidator::prior_bound() const {
  if (!prior_) return std::nullopt;
  const double q99 = prior_->summary().held_out_nll_q99;
  return std::isfinite(q99) ? std::optional<double>(q99) : std::nullopt;
}

const std::vector<double>& PoseValidator::reference_bone_lengths() const {
  static const std::vector<double> none;
  return prior_ ? prior_->bone_lengths() : none;
}

SampleValidity PoseValidator::Score(const float* positions, int frames) const {
  SampleValidity v;
  for (double f : ViolationFlags(positions, frames)) v.violating_frames += f > 0 ? 1 : 0;
  if (prior_ && frames > 0) {
    double sum = 0;
    for (double x : PriorNll(positions, frames)) sum += x;
    v.prior_nll = sum / frames;
    const std::optional<double> bound = prior_bound();
    // A NaN mean (a degenerate pose) is not within any bound.
    v.prior_ok = !bound || *v.prior_nll <= *bound;
  }
  v.valid = v.violating_frames == 0 && v.prior_ok;
  return v;
}

void AttachToBundle(const std::string& bundle_dir, const std::string& constraints_yaml,
                    const std::string& prior_dir) {
  const fs::path dir(bundle_dir);
  fs::create_directories(dir);
  if (!constraints_yaml.empty()) {
    WriteFileAtomically((dir / "constraints.yaml").string(), ReadFileBytes(constraints_yaml));
  }
  if (!prior_dir.empty()) {
    // The prior is loaded first: a broken prior is refused here, not when the bundle is used.
    SavePosePrior(LoadPosePrior(prior_dir), (dir / "prior").string());
  }
}

}  // namespace motionfork
