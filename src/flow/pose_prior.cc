#include "flow/pose_prior.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <stdexcept>

#include "core/error.h"
#include "core/limbs.h"
#include "flow/flow_module.h"
#include "io/file_util.h"
#include "io/npy.h"

namespace motionfork {
namespace {

constexpr int64_t kChunk = 16384;  // poses per forward pass when scoring many

std::string SkeletonText(const Skeleton& s) {
  return "'" + s.name() + "' (" + std::to_string(s.num_joints()) + " joints)";
}

}  // namespace

struct PosePrior::Impl {
  std::shared_ptr<const Skeleton> skeleton;
  PriorConfig config;
  std::string skeleton_config;
  std::vector<double> bone_lengths;
  PriorTrainingSummary summary;
  PoseFlow flow{nullptr};
  int dim = 0;
};

PosePrior::PosePrior(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

PosePrior::PosePrior(std::shared_ptr<const Skeleton> skeleton, const PriorConfig& config)
    : impl_(std::make_unique<Impl>()) {
  if (!skeleton) throw std::invalid_argument("PosePrior: expected a skeleton, got null");
  if (skeleton->is_anonymous()) {
    throw std::invalid_argument("PosePrior: skeleton " + SkeletonText(*skeleton) +
                                " has unnamed or unlinked joints: limb directions need a real "
                                "joint tree (use a skeleton config)");
  }
  if (skeleton->num_joints() < 2) {
    throw std::invalid_argument("PosePrior: expected a skeleton with >= 2 joints, got " +
                                std::to_string(skeleton->num_joints()));
  }
  ValidatePriorConfig(config);
  impl_->skeleton = std::move(skeleton);
  impl_->dim = 3 * (impl_->skeleton->num_joints() - 1);
  impl_->flow = PoseFlow(impl_->dim, config.model);
  impl_->flow->Initialize(config.training.seed);
  impl_->config = config;
  impl_->config.model = impl_->flow->options();  // reflections resolved (0 -> dim)
  impl_->bone_lengths.assign(impl_->skeleton->num_joints() - 1, 0.1);
}

PosePrior::~PosePrior() = default;
PosePrior::PosePrior(PosePrior&&) noexcept = default;
PosePrior& PosePrior::operator=(PosePrior&&) noexcept = default;

const Skeleton& PosePrior::skeleton() const { return *impl_->skeleton; }
const std::shared_ptr<const Skeleton>& PosePrior::skeleton_ptr() const { return impl_->skeleton; }
int PosePrior::dim() const { return impl_->dim; }
const PriorConfig& PosePrior::config() const { return impl_->config; }
int64_t PosePrior::num_parameters() const { return impl_->flow->NumParameters(); }
const std::string& PosePrior::skeleton_config() const { return impl_->skeleton_config; }
void PosePrior::set_skeleton_config(const std::string& name) { impl_->skeleton_config = name; }
const std::vector<double>& PosePrior::bone_lengths() const { return impl_->bone_lengths; }
const PriorTrainingSummary& PosePrior::summary() const { return impl_->summary; }
PriorTrainingSummary& PosePrior::mutable_summary() { return impl_->summary; }
PoseFlow& PosePrior::module() { return impl_->flow; }
const PoseFlow& PosePrior::module() const { return impl_->flow; }

void PosePrior::set_bone_lengths(std::vector<double> lengths) {
  const size_t expected = impl_->skeleton->num_joints() - 1;
  if (lengths.size() != expected) {
    throw std::invalid_argument("PosePrior: expected " + std::to_string(expected) +
                                " bone lengths, got " + std::to_string(lengths.size()));
  }
  for (size_t k = 0; k < lengths.size(); ++k) {
    if (!(lengths[k] > 0) || !std::isfinite(lengths[k])) {
      throw std::invalid_argument("PosePrior: bone length " + std::to_string(k) + " ('" +
                                  impl_->skeleton->joint_name(static_cast<int>(k) + 1) +
                                  "') must be > 0 metres, got " + std::to_string(lengths[k]));
    }
  }
  impl_->bone_lengths = std::move(lengths);
}

void PosePrior::CheckSkeleton(const Skeleton& other) const {
  const Skeleton& mine = *impl_->skeleton;
  const std::string hint = impl_->skeleton_config.empty()
                               ? std::string(" (map the motion onto the prior's skeleton first)")
                               : " (map the motion onto the prior's skeleton, e.g. --skeleton " +
                                     impl_->skeleton_config + ")";
  if (other.num_joints() != mine.num_joints()) {
    throw std::invalid_argument("the prior expects poses of skeleton " + SkeletonText(mine) +
                                ", expected " + std::to_string(mine.num_joints()) +
                                " joints, got " + std::to_string(other.num_joints()) +
                                " (skeleton '" + other.name() + "')" + hint);
  }
  if (other.is_anonymous()) {
    throw std::invalid_argument("the motion's joints are unnamed or unlinked (skeleton '" +
                                other.name() + "'); the prior needs skeleton " +
                                SkeletonText(mine) + hint);
  }
  for (int j = 0; j < mine.num_joints(); ++j) {
    const bool same_name = other.joint_name(j) == mine.joint_name(j);
    const bool same_parent = other.parent(j) == mine.parent(j);
    if (!same_name || !same_parent) {
      auto describe = [j](const Skeleton& s) {
        return "'" + s.joint_name(j) + "' (parent " +
               (s.parent(j) < 0 ? std::string("none") : "'" + s.joint_name(s.parent(j)) + "'") +
               ")";
      };
      throw std::invalid_argument("the prior was trained on skeleton " + SkeletonText(mine) +
                                  ", the motion's skeleton '" + other.name() +
                                  "' differs at joint " + std::to_string(j) + ": expected " +
                                  describe(mine) + ", got " + describe(other) + hint);
    }
  }
}

std::vector<double> PosePrior::LogProbDirections(const std::vector<float>& directions) const {
  const int64_t D = impl_->dim;
  if (directions.size() % D != 0) {
    throw std::invalid_argument("PosePrior::LogProbDirections: expected [N, " + std::to_string(D) +
                                "] values (a multiple of " + std::to_string(D) + "), got " +
                                std::to_string(directions.size()));
  }
  const int64_t n = static_cast<int64_t>(directions.size()) / D;
  const int limbs = static_cast<int>(D / 3);
  for (int64_t i = 0; i < n; ++i) {
    for (int k = 0; k < limbs; ++k) {
      const float* d = &directions[static_cast<size_t>(i * D + 3 * k)];
      const std::string where = "pose " + std::to_string(i) + ", limb " + std::to_string(k) +
                                " (ending at '" + impl_->skeleton->joint_name(k + 1) + "')";
      if (!std::isfinite(d[0]) || !std::isfinite(d[1]) || !std::isfinite(d[2])) {
        throw std::invalid_argument("PosePrior: " + where +
                                    ": expected finite numbers, got NaN or Inf");
      }
      const double len = std::sqrt(double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2]);
      if (std::abs(len - 1.0) > 1e-3) {
        throw std::invalid_argument("PosePrior: " + where +
                                    ": expected a unit direction, got length " +
                                    std::to_string(len));
      }
    }
  }
  std::vector<double> out(static_cast<size_t>(n));
  c10::InferenceMode guard;
  for (int64_t begin = 0; begin < n; begin += kChunk) {
    const int64_t count = std::min(kChunk, n - begin);
    const torch::Tensor x = torch::from_blob(const_cast<float*>(directions.data()) + begin * D,
                                             {count, D}, torch::kFloat32);
    const torch::Tensor lp = impl_->flow->log_prob(x).to(torch::kFloat64).contiguous();
    std::copy(lp.data_ptr<double>(), lp.data_ptr<double>() + count, out.begin() + begin);
  }
  return out;
}

std::vector<double> PosePrior::LogProb(const Motion& motion) const {
  CheckSkeleton(motion.skeleton());
  return LogProbDirections(ToLimbs(motion).directions);
}

namespace {

std::vector<float> Apply(const PoseFlow& flow, const std::vector<float>& in, int64_t D,
                         bool inverse, const char* what) {
  if (in.size() % D != 0) {
    throw std::invalid_argument(std::string("PosePrior::") + what + ": expected [N, " +
                                std::to_string(D) + "] values, got " + std::to_string(in.size()));
  }
  for (size_t i = 0; i < in.size(); ++i) {
    if (!std::isfinite(in[i])) {
      throw std::invalid_argument(std::string("PosePrior::") + what + ": value " +
                                  std::to_string(i % D) + " of row " + std::to_string(i / D) +
                                  " is NaN or Inf");
    }
  }
  const int64_t n = static_cast<int64_t>(in.size()) / D;
  std::vector<float> out(in.size());
  c10::InferenceMode guard;
  for (int64_t begin = 0; begin < n; begin += kChunk) {
    const int64_t count = std::min(kChunk, n - begin);
    const torch::Tensor x =
        torch::from_blob(const_cast<float*>(in.data()) + begin * D, {count, D}, torch::kFloat32);
    const torch::Tensor y = (inverse ? flow->inverse(x) : flow->forward(x).first).contiguous();
    std::copy(y.data_ptr<float>(), y.data_ptr<float>() + count * D, out.begin() + begin * D);
  }
  return out;
}

}  // namespace

std::vector<float> PosePrior::Forward(const std::vector<float>& directions) const {
  return Apply(impl_->flow, directions, impl_->dim, false, "Forward");
}

std::vector<float> PosePrior::Inverse(const std::vector<float>& latents) const {
  return Apply(impl_->flow, latents, impl_->dim, true, "Inverse");
}

namespace {

// Each limb's 3 numbers scaled to unit length: [N, D] -> [N, D]. (A zero vector stays zero; it
// has measure zero under the flow.)
torch::Tensor NormalizeLimbs(const torch::Tensor& x) {
  const torch::Tensor v = x.view({x.size(0), -1, 3});
  return (v / v.norm(2, -1, true).clamp_min(1e-12)).view({x.size(0), -1});
}

}  // namespace

Motion PosePrior::Sample(int n, uint64_t seed, double temperature,
                         const std::vector<double>& bone_lengths, double fps,
                         int mcmc_steps) const {
  if (n < 1)
    throw std::invalid_argument("PosePrior::Sample: expected n >= 1, got " + std::to_string(n));
  if (!(temperature > 0) || !std::isfinite(temperature)) {
    throw std::invalid_argument("PosePrior::Sample: expected temperature > 0, got " +
                                std::to_string(temperature));
  }
  if (mcmc_steps < 0) {
    throw std::invalid_argument("PosePrior::Sample: expected mcmc_steps >= 0, got " +
                                std::to_string(mcmc_steps));
  }
  const std::vector<double>& lengths = bone_lengths.empty() ? impl_->bone_lengths : bone_lengths;
  const int L = impl_->skeleton->num_joints() - 1;
  if (static_cast<int>(lengths.size()) != L) {
    throw std::invalid_argument("PosePrior::Sample: expected " + std::to_string(L) +
                                " bone lengths, got " + std::to_string(lengths.size()));
  }
  c10::InferenceMode guard;
  at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(seed);
  const PoseFlow& flow = impl_->flow;
  const int64_t D = impl_->dim;
  torch::Tensor x = NormalizeLimbs(flow->inverse(torch::randn({n, D}, gen) * temperature));
  torch::Tensor lp = flow->log_prob(x) / temperature;
  double step = 0.05;  // per-number proposal standard deviation
  for (int s = 0; s < mcmc_steps; ++s) {
    // Random-walk proposal on the product of spheres: perturb, re-normalise. Its density depends
    // only on the angle moved, so it is symmetric and the plain Metropolis ratio applies.
    const torch::Tensor proposal = NormalizeLimbs(x + step * torch::randn({n, D}, gen));
    const torch::Tensor lp_new = flow->log_prob(proposal) / temperature;
    const torch::Tensor accept = torch::rand({n}, gen).log() < (lp_new - lp);
    x = torch::where(accept.unsqueeze(1), proposal, x);
    lp = torch::where(accept, lp_new, lp);
    if (s < mcmc_steps / 2) {  // adapt during burn-in only
      const double rate = accept.to(torch::kFloat64).mean().item<double>();
      step *= rate < 0.2 ? 0.95 : rate > 0.3 ? 1.05 : 1.0;
    }
  }
  const torch::Tensor dirs = x.contiguous();
  Limbs limbs;
  limbs.num_frames = n;
  limbs.num_limbs = L;
  limbs.root.assign(static_cast<size_t>(n) * 3, 0.0f);
  limbs.directions.assign(dirs.data_ptr<float>(), dirs.data_ptr<float>() + dirs.numel());
  limbs.lengths.resize(static_cast<size_t>(n) * L);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < L; ++k) {
      limbs.lengths[static_cast<size_t>(i) * L + k] = static_cast<float>(lengths[k]);
      float* d = &limbs.directions[(static_cast<size_t>(i) * L + k) * 3];
      if (d[0] == 0 && d[1] == 0 && d[2] == 0)
        d[1] = 1;  // measure zero; FromLimbs needs a direction
    }
  }
  return FromLimbs(impl_->skeleton, fps, limbs);
}

}  // namespace motionfork
