#include "imputation/motion_sampling.h"

#include <algorithm>
#include <memory>
#include <vector>

namespace motionfork {

Motion SampleMotion(const HgvaeModel& model, int count, int class_index, uint64_t seed,
                    bool sampled) {
  const std::vector<float> w = model.Sample(count, class_index, seed, sampled);
  const int T = model.window(), N = model.coords(), J = model.skeleton().num_joints();
  const auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  std::vector<float> pos(static_cast<size_t>(count) * T * J * 3, 0.0f);
  for (size_t f = 0; f < static_cast<size_t>(count) * T; ++f) {
    std::copy(w.begin() + f * N, w.begin() + (f + 1) * N, pos.begin() + f * J * 3 + 3);
  }
  return Motion(skeleton, model.manifest().fps, std::move(pos));
}

}  // namespace motionfork
