#include "eval/baselines.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/limbs.h"

namespace motionfork {
namespace {

void CheckLengths(const char* who, int t_his, int t_pred) {
  if (t_his < 1 || t_pred < 1) {
    throw std::invalid_argument(std::string(who) +
                                ": expected t_his >= 1 and t_pred >= 1 frames, got " +
                                std::to_string(t_his) + " and " + std::to_string(t_pred));
  }
}

}  // namespace

ZeroVelocityPredictor::ZeroVelocityPredictor(std::shared_ptr<const Skeleton> skeleton, int t_his,
                                             int t_pred)
    : skeleton_(std::move(skeleton)), t_his_(t_his), t_pred_(t_pred) {
  if (!skeleton_) throw std::invalid_argument("zero-velocity: expected a skeleton, got null");
  CheckLengths("zero-velocity", t_his, t_pred);
}

void ZeroVelocityPredictor::DoPredict(const float* history, const PredictRequest& request,
                                      float* futures) {
  const size_t pose = static_cast<size_t>(skeleton_->num_joints()) * 3;
  const float* last = history + static_cast<size_t>(t_his_ - 1) * pose;
  for (int f = 0; f < request.num_samples * t_pred_; ++f) {
    std::copy(last, last + pose, futures + f * pose);
  }
}

NearestNeighbourPredictor::NearestNeighbourPredictor(std::vector<const Motion*> training, int t_his,
                                                     int t_pred,
                                                     const NearestNeighbourOptions& options)
    : training_(std::move(training)), t_his_(t_his), t_pred_(t_pred), options_(options) {
  CheckLengths("nearest neighbours", t_his, t_pred);
  if (options_.stride < 1) {
    throw std::invalid_argument("nearest neighbours: expected stride >= 1 frame, got " +
                                std::to_string(options_.stride));
  }
  std::vector<int> frames;
  for (const Motion* m : training_) {
    if (!m) throw std::invalid_argument("nearest neighbours: expected training motions, got null");
    if (!skeleton_) skeleton_ = m->skeleton_ptr();
    if (!m->skeleton().SameStructure(*skeleton_)) {
      throw std::invalid_argument("nearest neighbours: training motions on skeletons '" +
                                  skeleton_->name() + "' and '" + m->skeleton().name() +
                                  "'; expected one skeleton");
    }
    if (m->fps() != training_.front()->fps()) {
      throw std::invalid_argument("nearest neighbours: training motions at " +
                                  std::to_string(training_.front()->fps()) + " Hz and " +
                                  std::to_string(m->fps()) + " Hz; expected one frame rate");
    }
    frames.push_back(m->num_frames());
  }
  windows_ = SlidingWindows(frames, t_his + t_pred, options_.stride, options_.include_last);
  if (windows_.empty()) {
    throw std::invalid_argument("nearest neighbours: " + std::to_string(training_.size()) +
                                " training clips, none with the " + std::to_string(t_his + t_pred) +
                                " frames one window needs");
  }
  const int J = skeleton_->num_joints();
  dims_ = 3 * (J - 1);
  keys_.resize(windows_.size() * dims_);
  for (size_t w = 0; w < windows_.size(); ++w) {
    const float* f = training_[windows_[w].clip]->frame(windows_[w].start + t_his - 1);
    float* key = keys_.data() + w * dims_;
    for (int j = 1; j < J; ++j) {
      for (int a = 0; a < 3; ++a) key[3 * (j - 1) + a] = f[3 * j + a] - f[a];
    }
  }
}

std::string NearestNeighbourPredictor::description() const {
  return std::to_string(windows_.size()) + " training windows from " +
         std::to_string(training_.size()) + " clips, stride " + std::to_string(options_.stride) +
         (options_.include_last ? ", last start included" : ", last start excluded") +
         "; futures re-targeted to the history's bone lengths";
}

std::vector<int> NearestNeighbourPredictor::Neighbours(const float* history, int K) const {
  if (K < 1 || K > num_training_windows()) {
    throw std::invalid_argument("nearest neighbours: expected K in [1, " +
                                std::to_string(num_training_windows()) +
                                "] (the training windows), got " + std::to_string(K));
  }
  const int J = skeleton_->num_joints();
  const float* f = history + static_cast<size_t>(t_his_ - 1) * J * 3;
  std::vector<double> query(dims_);
  for (int j = 1; j < J; ++j) {
    for (int a = 0; a < 3; ++a) query[3 * (j - 1) + a] = double(f[3 * j + a]) - double(f[a]);
  }
  std::vector<std::pair<double, int>> dist(windows_.size());
  for (size_t w = 0; w < windows_.size(); ++w) {
    const float* key = keys_.data() + w * dims_;
    double d2 = 0;
    for (int e = 0; e < dims_; ++e) {
      const double d = query[e] - double(key[e]);
      d2 += d * d;
    }
    dist[w] = {std::sqrt(d2), static_cast<int>(w)};
  }
  // Pairs compare by distance, then index: ties keep the lower window index.
  std::partial_sort(dist.begin(), dist.begin() + K, dist.end());
  std::vector<int> out(K);
  for (int k = 0; k < K; ++k) out[k] = dist[k].second;
  return out;
}

void NearestNeighbourPredictor::DoPredict(const float* history, const PredictRequest& request,
                                          float* futures) {
  const int K = request.num_samples;
  const int J = skeleton_->num_joints();
  const std::vector<int> near = Neighbours(history, K);

  // Bone lengths [J - 1] and root [3] of the history's last frame.
  const float* last = history + static_cast<size_t>(t_his_ - 1) * J * 3;
  std::vector<float> lengths(J - 1);
  for (int j = 1; j < J; ++j) {
    const float* c = last + 3 * j;
    const float* p = last + 3 * skeleton_->parent(j);
    const double v[3] = {double(c[0]) - p[0], double(c[1]) - p[1], double(c[2]) - p[2]};
    lengths[j - 1] = static_cast<float>(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }

  auto future_limbs = [&](int window) {
    const Window& w = windows_[window];
    return ToLimbs(training_[w.clip]->Slice(w.start + t_his_, w.start + t_his_ + t_pred_));
  };
  std::vector<int> fixed_limbs;  // limb k ends at joint k + 1
  Limbs fixed;
  if (request.fixed_part >= 0) {
    for (int j : skeleton_->GetPartition().parts[request.fixed_part].joints) {
      fixed_limbs.push_back(j - 1);
    }
    fixed = future_limbs(near[0]);
  }
  const size_t sample_size = static_cast<size_t>(t_pred_) * J * 3;
  for (int k = 0; k < K; ++k) {
    const Window& w = windows_[near[k]];
    const Motion& m = *training_[w.clip];
    Limbs limbs = future_limbs(near[k]);
    for (int t = 0; t < t_pred_; ++t) {
      for (int l = 0; l < J - 1; ++l)
        limbs.lengths[static_cast<size_t>(t) * (J - 1) + l] = lengths[l];
      for (int l : fixed_limbs) {
        const size_t at = (static_cast<size_t>(t) * (J - 1) + l) * 3;
        std::copy(fixed.directions.begin() + at, fixed.directions.begin() + at + 3,
                  limbs.directions.begin() + at);
      }
      const float* from = m.at(w.start + t_his_ - 1, 0);
      for (int a = 0; a < 3; ++a) limbs.root[3 * t + a] += last[a] - from[a];
    }
    const Motion out = FromLimbs(skeleton_, m.fps(), limbs);
    std::copy(out.positions().begin(), out.positions().end(), futures + k * sample_size);
  }
}

}  // namespace motionfork
