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

LastPoseBaseline::LastPoseBaseline(const char* who, std::shared_ptr<const Skeleton> skeleton,
                                   int t_his, int t_pred)
    : skeleton_(std::move(skeleton)), t_his_(t_his), t_pred_(t_pred) {
  if (!skeleton_) throw std::invalid_argument(std::string(who) + ": expected a skeleton, got null");
  CheckLengths(who, t_his, t_pred);
}

void ZeroVelocityPredictor::DoPredict(const float* history, const PredictRequest& request,
                                      float* futures) {
  const size_t pose = static_cast<size_t>(skeleton_->num_joints()) * 3;
  const float* last = history + static_cast<size_t>(t_his_ - 1) * pose;
  for (int f = 0; f < request.num_samples * t_pred_; ++f) {
    std::copy(last, last + pose, futures + f * pose);
  }
}

ConstantVelocityPredictor::ConstantVelocityPredictor(std::shared_ptr<const Skeleton> skeleton,
                                                     int t_his, int t_pred, UpAxis up,
                                                     const ConstantVelocityOptions& options)
    : LastPoseBaseline("constant velocity", std::move(skeleton), t_his, t_pred),
      up_(up),
      frames_(options.frames == 0 ? t_his - 1 : options.frames),
      turn_(options.turn) {
  if (t_his < 2 || options.frames < 0 || options.frames > t_his - 1) {
    throw std::invalid_argument(
        "constant velocity: expected t_his >= 2 and 0 <= frames <= t_his - 1 (0: all), got "
        "t_his " +
        std::to_string(t_his) + ", frames " + std::to_string(options.frames));
  }
  GroundAxes(up);  // throws for a bad up axis
}

std::string ConstantVelocityPredictor::description() const {
  return std::string("the last pose carried on by the root's velocity") +
         (turn_ ? " and the pelvis's turn rate" : "") + " over the history's last " +
         std::to_string(frames_) + " frame step" + (frames_ == 1 ? "" : "s");
}

void ConstantVelocityPredictor::DoPredict(const float* history, const PredictRequest& request,
                                          float* futures) {
  const int J = skeleton_->num_joints();
  const size_t pose = static_cast<size_t>(J) * 3;
  const auto [a, b] = GroundAxes(up_);
  // The turn is measured and applied in the same (a, b) plane, so the up axis's sign does not
  // matter.
  const float* last = history + static_cast<size_t>(t_his_ - 1) * pose;
  const float* first = history + static_cast<size_t>(t_his_ - 1 - frames_) * pose;
  double velocity[3];
  for (int c = 0; c < 3; ++c) velocity[c] = (static_cast<double>(last[c]) - first[c]) / frames_;
  velocity[up_.axis] = 0;  // the height kept: a pelvis's bob carried on would sink or fly
  // The turn of each step: the rotation in the (a, b) plane that best maps the earlier frame's
  // pelvis (the joints hanging on the root) onto the later's (atan2 of the summed cross and dot
  // products).
  double turn = 0;
  for (int t = t_his_ - frames_; turn_ && t < t_his_; ++t) {
    const float* p = history + static_cast<size_t>(t - 1) * pose;
    const float* q = history + static_cast<size_t>(t) * pose;
    double cross = 0, dot = 0;
    for (int j = 1; j < J; ++j) {
      if (skeleton_->parent(j) != 0) continue;
      const double pa = p[3 * j + a] - p[a], pb = p[3 * j + b] - p[b];
      const double qa = q[3 * j + a] - q[a], qb = q[3 * j + b] - q[b];
      cross += pa * qb - pb * qa;
      dot += pa * qa + pb * qb;
    }
    turn += std::atan2(cross, dot) / frames_;
  }
  float* out = futures;
  double root[3] = {last[0], last[1], last[2]};
  for (int t = 1; t <= t_pred_; ++t, out += pose) {
    const double c = std::cos(turn * t), s = std::sin(turn * t);
    // The velocity turns with the body: step t moves by the mean velocity rotated t turns.
    double step[3] = {velocity[0], velocity[1], velocity[2]};
    step[a] = c * velocity[a] - s * velocity[b];
    step[b] = s * velocity[a] + c * velocity[b];
    for (int e = 0; e < 3; ++e) root[e] += step[e];
    for (int j = 0; j < J; ++j) {
      double rel[3];
      for (int e = 0; e < 3; ++e) rel[e] = static_cast<double>(last[3 * j + e]) - last[e];
      const double ra = c * rel[a] - s * rel[b], rb = s * rel[a] + c * rel[b];
      rel[a] = ra;
      rel[b] = rb;
      for (int e = 0; e < 3; ++e) out[3 * j + e] = static_cast<float>(root[e] + rel[e]);
    }
  }
  for (int k = 1; k < request.num_samples; ++k) {
    std::copy(futures, futures + t_pred_ * pose, futures + static_cast<size_t>(k) * t_pred_ * pose);
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
