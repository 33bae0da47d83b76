// Non-learned baselines any user can run on any protocol.
//
// - zero-velocity: every sample repeats the last observed pose (APD 0 by construction);
// - constant velocity: the last pose carried on by the root's velocity (and, if asked, the
//   pelvis's turn rate): the root trajectory's classical baseline (issue 27);
// - nearest neighbours: the K training futures whose history ends closest to this history's last
//   pose, re-targeted to this history's bone lengths.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/motion.h"
#include "dataset/windows.h"
#include "eval/predictor.h"
#include "eval/root_motion.h"

namespace motionfork {

// What the baselines that copy the last pose share: the skeleton and lengths they work on, and
// every sample's parts already shared (the controllable setting holds by construction).
class LastPoseBaseline : public Predictor {
 public:
  const Skeleton& skeleton() const override { return *skeleton_; }
  int t_his() const override { return t_his_; }
  int t_pred() const override { return t_pred_; }
  bool SupportsFixedPart() const override { return true; }

 protected:
  // Throws std::invalid_argument (naming `who`) for a null skeleton or t_his, t_pred < 1.
  LastPoseBaseline(const char* who, std::shared_ptr<const Skeleton> skeleton, int t_his,
                   int t_pred);
  std::shared_ptr<const Skeleton> skeleton_;
  int t_his_, t_pred_;
};

class ZeroVelocityPredictor : public LastPoseBaseline {
 public:
  ZeroVelocityPredictor(std::shared_ptr<const Skeleton> skeleton, int t_his, int t_pred)
      : LastPoseBaseline("zero-velocity", std::move(skeleton), t_his, t_pred) {}

  std::string name() const override { return "zero-velocity"; }
  std::string description() const override { return "every sample repeats the last observed pose"; }

 protected:
  void DoPredict(const float* history, const PredictRequest& request, float* futures) override;
};

struct ConstantVelocityOptions {
  // Frame steps of the history the velocity (and turn rate) are means over: 1 = the last step
  // alone, 0 = the whole history (t_his - 1 steps).
  int frames = 0;
  // Whether the body keeps turning at the pelvis's turn rate (the velocity turning with it).
  bool turn = false;
};

// Every sample: the last observed pose, its root moving on at the history's mean velocity on the
// ground plane, its height kept; with `turn`, pose and velocity also turn about the up axis at the
// pelvis's mean turn rate (the best-fitting rotation of the joints hanging on the root between
// consecutive frames). The defaults were chosen on Bandai's validation clips (every 10th training
// clip): the whole history and no turn gave the lowest root FDE (0.393 m against 0.894 m for the
// last step with the whole body's turn, 0.495 m with the pelvis's turn over the whole history).
class ConstantVelocityPredictor : public LastPoseBaseline {
 public:
  // Throws std::invalid_argument for a null skeleton, t_his < 2, t_pred < 1, frames outside
  // [0, t_his - 1] or a bad up axis.
  ConstantVelocityPredictor(std::shared_ptr<const Skeleton> skeleton, int t_his, int t_pred,
                            UpAxis up, const ConstantVelocityOptions& options = {});

  std::string name() const override { return "constant-velocity"; }
  std::string description() const override;

 protected:
  void DoPredict(const float* history, const PredictRequest& request, float* futures) override;

 private:
  UpAxis up_;
  int frames_;
  bool turn_;
};

struct NearestNeighbourOptions {
  // Frames between the starts of consecutive training windows in a clip.
  int stride = 5;
  // SlidingWindows' rule: true takes starts 0, stride, ... up to and including T - (t_his +
  // t_pred); false stops strictly below it (DLow's rule for test windows). Bandai: 29,064
  // training windows with true.
  bool include_last = true;
};

// Training windows slide over every training clip (stride, include_last); each window's key is its
// last history pose as a root-relative pose vector without the root. For a history, the K windows
// whose key is nearest (L2 over the whole pose vector, metres, double precision) give the K
// samples, nearest first; equal distances keep the lower window index (clip order, then start).
// Each future is re-targeted: per frame, the limb directions of the training future with the bone
// lengths of the history's last frame (so the body keeps the observed proportions), the root
// moving as the training root moved after its history's last frame, from this history's last
// root (translated, not rotated: the protocol's metrics are root-relative).
// With a fixed part (controllable setting), that part's limb directions come from the nearest
// window in every sample, the other limbs from each sample's own window.
class NearestNeighbourPredictor : public Predictor {
 public:
  // training: clips on one skeleton, at one frame rate (the protocol's); they must outlive the
  // predictor. Throws std::invalid_argument when they give no window or their skeletons differ.
  NearestNeighbourPredictor(std::vector<const Motion*> training, int t_his, int t_pred,
                            const NearestNeighbourOptions& options = {});

  std::string name() const override { return "nearest-neighbours"; }
  std::string description() const override;
  const Skeleton& skeleton() const override { return *skeleton_; }
  int t_his() const override { return t_his_; }
  int t_pred() const override { return t_pred_; }
  bool SupportsFixedPart() const override { return true; }

  int num_training_windows() const { return static_cast<int>(windows_.size()); }
  // Window::clip indexes the training clips as given.
  const Window& training_window(int i) const { return windows_.at(i); }
  // The K nearest training windows to a history's last pose (history: [t_his, J, 3] metres),
  // nearest first. Throws std::invalid_argument for K outside [1, num_training_windows()].
  std::vector<int> Neighbours(const float* history, int K) const;

 protected:
  void DoPredict(const float* history, const PredictRequest& request, float* futures) override;

 private:
  std::vector<const Motion*> training_;
  std::shared_ptr<const Skeleton> skeleton_;
  int t_his_, t_pred_;
  NearestNeighbourOptions options_;
  std::vector<Window> windows_;
  std::vector<float> keys_;  // [num windows, D] last history pose vectors, metres
  int dims_ = 0;             // D = 3 (J - 1)
};

}  // namespace motionfork
