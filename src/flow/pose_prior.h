// PosePrior: a learned density over poses (the GSPS normalizing flow on limb directions) bound to
// a skeleton, without LibTorch in its interface. It scores poses (log-density, nats), maps poses
// to latents and back and samples poses; bundle/prior_bundle.h saves and loads it as a bundle:
//
//   DIR/prior.yaml    format, skeleton (joints + parents), mean bone lengths, config, training
//                     summary, the parameter layout and a checksum of the weights
//   DIR/weights.npy   float32 [P]: every parameter concatenated in the listed order
//
// A pose is scored through its unit limb directions, one per non-root joint
// ((joint - parent) / |joint - parent|, limb k ends at joint k + 1), D = 3 (J - 1) numbers
// (48 for 17 joints). Bone lengths and the root position do not matter.
//
// Const methods may be called from several threads at once.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/motion.h"
#include "core/skeleton.h"
#include "flow/flow_options.h"

namespace motionfork {

class PoseFlow;  // flow/flow_module.h (LibTorch)

class PosePrior {
 public:
  // An untrained prior for a skeleton (named joints with a real tree, >= 2 joints), weights
  // initialised from config.training.seed. Throws std::invalid_argument for a bad config
  // (naming the field) or an anonymous skeleton.
  PosePrior(std::shared_ptr<const Skeleton> skeleton, const PriorConfig& config);
  ~PosePrior();
  PosePrior(PosePrior&&) noexcept;
  PosePrior& operator=(PosePrior&&) noexcept;

  // Bundles on disk (DIR/prior.yaml, DIR/weights.npy): bundle/prior_bundle.h (LoadPosePrior,
  // SavePosePrior).

  const Skeleton& skeleton() const;
  const std::shared_ptr<const Skeleton>& skeleton_ptr() const;
  // D = 3 (J - 1).
  int dim() const;
  const PriorConfig& config() const;
  int64_t num_parameters() const;

  // Name of the skeleton config the prior was trained with ("bandai"), used to map files of the
  // dataset's source skeleton onto the prior's; "" when unknown.
  const std::string& skeleton_config() const;
  void set_skeleton_config(const std::string& name);
  // [J-1] metres: default bone lengths for Sample (the training frames' means; 0.1 m untrained).
  const std::vector<double>& bone_lengths() const;
  void set_bone_lengths(std::vector<double> lengths);
  const PriorTrainingSummary& summary() const;
  PriorTrainingSummary& mutable_summary();

  // Throws std::invalid_argument unless `other` has the prior's joints and parents, saying what
  // differs (joint count, or the first joint whose name or parent differs) and how to fix it.
  void CheckSkeleton(const Skeleton& other) const;

  // directions: [N, D] unit vectors -> log p [N], nats. Throws std::invalid_argument for a size
  // that is not a multiple of D, a non-finite value or a vector whose length is not 1 (+- 1e-3),
  // naming the pose and the limb.
  std::vector<double> LogProbDirections(const std::vector<float>& directions) const;
  // One log-density per frame of a motion on the prior's skeleton (positions in metres).
  // Throws std::invalid_argument for another skeleton or a zero-length bone (naming frame and
  // bone).
  std::vector<double> LogProb(const Motion& motion) const;

  // Pose -> latent and back: [N, D] -> [N, D]. Inverse returns the network's exact inverse,
  // not re-normalised to unit limbs.
  std::vector<float> Forward(const std::vector<float>& directions) const;
  std::vector<float> Inverse(const std::vector<float>& latents) const;

  // n poses from the prior's density restricted to valid poses (unit limb directions),
  // p(d)^(1 / temperature): latents z ~ N(0, temperature^2 I) inverted through the flow and each
  // limb direction normalised, then `mcmc_steps` Metropolis-Hastings steps on unit directions
  // (all limbs perturbed together, step size adapted in the first half to ~25% acceptance).
  // Why the chain: the flow is a density on R^D and puts much of its mass off the unit-limb
  // manifold, so its raw samples, once normalised, are rarely plausible poses (mcmc_steps = 0
  // gives them). Poses are laid out with bone_lengths ([J-1] metres; empty = bone_lengths()),
  // root at the origin; frames of the returned motion are independent poses, at `fps` Hz.
  // Deterministic for a seed (and thread count).
  Motion Sample(int n, uint64_t seed, double temperature = 1.0,
                const std::vector<double>& bone_lengths = {}, double fps = 30.0,
                int mcmc_steps = 1000) const;

  // The LibTorch module (include flow/flow_module.h to use it): for training, or to score poses
  // inside another network's graph.
  PoseFlow& module();
  const PoseFlow& module() const;

 private:
  struct Impl;
  explicit PosePrior(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace motionfork
