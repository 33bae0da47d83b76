#include "flow/prior_data.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/limbs.h"

namespace motionfork {
namespace {

// A per-clip hash mixed with the seed: which clips are held out depends on their names and the
// seed only, not on the order the dataset lists them in.
uint64_t ClipHash(const std::string& name, uint64_t seed) {
  uint64_t h = 1469598103934665603ull ^ (seed * 0x9E3779B97F4A7C15ull);
  for (unsigned char c : name) {
    h ^= c;
    h *= 1099511628211ull;
  }
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  return h;
}

}  // namespace

int64_t AppendDirections(const Motion& motion, int frame_stride, PriorFrames* out,
                         std::vector<double>* length_sums, int64_t* length_count) {
  if (frame_stride < 1) {
    throw std::invalid_argument("AppendDirections: expected frame_stride >= 1, got " +
                                std::to_string(frame_stride));
  }
  const int L = motion.num_joints() - 1;
  if (out->dim == 0) out->dim = 3 * L;
  if (out->dim != 3 * L) {
    throw std::invalid_argument("AppendDirections: expected " + std::to_string(out->dim / 3 + 1) +
                                " joints, got " + std::to_string(motion.num_joints()));
  }
  if (length_sums && length_sums->empty()) length_sums->assign(L, 0.0);
  const Limbs limbs = ToLimbs(motion, 0.0f);  // zero-length bones give NaN; skipped below
  int64_t dropped = 0;
  for (int t = 0; t < limbs.num_frames; t += frame_stride) {
    const float* len = &limbs.lengths[static_cast<size_t>(t) * L];
    bool ok = true;
    for (int k = 0; k < L; ++k) ok = ok && len[k] >= 1e-6f;
    if (!ok) {
      ++dropped;
      continue;
    }
    const float* d = &limbs.directions[static_cast<size_t>(t) * 3 * L];
    out->directions.insert(out->directions.end(), d, d + 3 * L);
    if (length_sums) {
      for (int k = 0; k < L; ++k) (*length_sums)[k] += len[k];
      ++*length_count;
    }
  }
  return dropped;
}

PriorData MakePriorData(const Dataset& dataset, const PriorTrainOptions& options) {
  const std::vector<int> train = dataset.ClipIndices(Split::kTrain);
  if (train.empty()) {
    throw std::invalid_argument("MakePriorData: protocol '" + dataset.protocol.name +
                                "' has no usable training clips in this data folder");
  }
  // Held out: the clips with the smallest seeded hashes, share rounded to nearest (at least one
  // when the share is > 0 and two or more clips exist).
  std::vector<std::pair<uint64_t, int>> order;
  for (int i : train) order.emplace_back(ClipHash(dataset.clips[i].name, options.seed), i);
  std::sort(order.begin(), order.end());
  size_t n_held = static_cast<size_t>(std::llround(options.held_out_share * train.size()));
  if (options.held_out_share > 0 && n_held == 0 && train.size() >= 2) n_held = 1;
  if (n_held >= train.size()) n_held = train.size() - 1;
  std::vector<bool> held(dataset.clips.size(), false);
  for (size_t k = 0; k < n_held; ++k) held[order[k].second] = true;

  PriorData data;
  const int dim = 3 * (dataset.skeleton.skeleton->num_joints() - 1);
  data.train.dim = data.held_out.dim = data.test.dim = dim;
  std::vector<double> sums;
  int64_t count = 0;
  for (size_t i = 0; i < dataset.clips.size(); ++i) {
    const Clip& c = dataset.clips[i];
    if (c.split == Split::kTest) {
      data.dropped_frames += AppendDirections(c.motion, options.frame_stride, &data.test);
    } else if (held[i]) {
      data.held_out_clips.push_back(c.name);
      data.dropped_frames += AppendDirections(c.motion, options.frame_stride, &data.held_out);
    } else {
      ++data.train_clips;
      data.dropped_frames +=
          AppendDirections(c.motion, options.frame_stride, &data.train, &sums, &count);
    }
  }
  if (count == 0)
    throw std::invalid_argument("MakePriorData: no training frame has a direction for every limb");
  data.bone_lengths.resize(sums.size());
  for (size_t k = 0; k < sums.size(); ++k) data.bone_lengths[k] = sums[k] / count;
  std::sort(data.held_out_clips.begin(), data.held_out_clips.end());
  return data;
}

}  // namespace motionfork
