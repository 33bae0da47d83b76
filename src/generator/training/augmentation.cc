#include "generator/training/augmentation.h"

#include <cmath>
#include <stdexcept>

#include "core/heading.h"
#include "core/motion_noise.h"
#include "generator/training/training_data.h"

namespace motionfork {

namespace {

// A factor drawn log-uniformly in [1 / most, most].
double LogUniform(double most, std::mt19937_64& rng) {
  const double l = std::log(most);
  return std::exp(std::uniform_real_distribution<double>(-l, l)(rng));
}

}  // namespace

std::vector<WindowAugmentation> DrawAugmentations(const AugmentationOptions& options, int count,
                                                  std::mt19937_64& rng) {
  std::vector<WindowAugmentation> out(static_cast<size_t>(count));
  for (WindowAugmentation& a : out) {
    if (options.mirror > 0)
      a.mirror = std::uniform_real_distribution<double>(0, 1)(rng) < options.mirror;
    if (options.scale > 1) a.scale = LogUniform(options.scale, rng);
    if (options.speed > 1) a.speed = LogUniform(options.speed, rng);
  }
  return out;
}

MirrorPlan MakeMirrorPlan(const Skeleton& skeleton, const TrainingWindows& data) {
  if (skeleton.left_right_pairs().empty()) {
    throw std::invalid_argument("augmentation.mirror: skeleton '" + skeleton.name() +
                                "' names no left/right joint pairs to exchange");
  }
  MirrorPlan plan;
  const int N = data.num_nodes;
  plan.partner.resize(N);
  for (int n = 0; n < N; ++n) plan.partner[n] = skeleton.Mirror(n + 1) - 1;
  const HeadingJoints hip = HeadingNodes(skeleton);
  double along[3] = {0, 0, 0};
  std::vector<float> window(static_cast<size_t>(data.num_frames()) * N * 3);
  for (size_t w = 0; w < data.windows.size(); ++w) {
    data.Gather(static_cast<int>(w), window.data());
    const float* last = window.data() + static_cast<size_t>(data.t_his - 1) * N * 3;
    for (int k = 0; k < 3; ++k)
      along[k] += std::abs(last[3 * hip.left + k] - last[3 * hip.right + k]);
  }
  for (int k = 1; k < 3; ++k)
    if (along[k] > along[plan.axis]) plan.axis = k;
  return plan;
}

void MirrorPoses(const MirrorPlan& plan, int frames, float* poses) {
  const int N = static_cast<int>(plan.partner.size());
  std::vector<float> pose(static_cast<size_t>(N) * 3);
  for (int t = 0; t < frames; ++t) {
    float* p = poses + static_cast<size_t>(t) * N * 3;
    pose.assign(p, p + static_cast<size_t>(N) * 3);
    for (int n = 0; n < N; ++n) {
      const int from = plan.partner[n];
      for (int k = 0; k < 3; ++k) p[3 * n + k] = pose[3 * from + k];
      p[3 * n + plan.axis] = -p[3 * n + plan.axis];
    }
  }
}

void ScalePoses(double factor, size_t count, float* poses) {
  const float f = static_cast<float>(factor);
  for (size_t i = 0; i < count; ++i) poses[i] *= f;
}

void AddNoise(double sd, size_t count, std::mt19937_64& rng, float* values) {
  if (sd <= 0) return;
  NoiseSpec gaussian;  // core/motion_noise.h's: every value + N(0, sd^2), in order
  gaussian.sigma = sd;
  AddNoise(gaussian, values, 1, static_cast<int>(count / 3), rng);
}

}  // namespace motionfork
