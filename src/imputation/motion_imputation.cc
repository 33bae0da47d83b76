#include "imputation/motion_imputation.h"

#include <algorithm>
#include <stdexcept>

#include "imputation/interpolation_fill.h"
#include "imputation/refiner_fills.h"

namespace motionfork {

std::vector<float> TrainingMeanPose(const HgvaeModel& model) {
  const std::vector<double>& mean = model.manifest().mean;
  std::vector<float> pose(3 + mean.size(), 0.0f);
  for (size_t v = 0; v < mean.size(); ++v) pose[3 + v] = static_cast<float>(mean[v]);
  return pose;
}

std::vector<int> CoveringWindowStarts(int frames, int window, int stride) {
  std::vector<int> starts;
  for (int s = 0; s + window <= frames; s += stride) starts.push_back(s);
  if (!starts.empty() && starts.back() + window < frames) starts.push_back(frames - window);
  return starts;
}

namespace {

void CheckMotion(const HgvaeModel& model, const Motion& motion) {
  if (motion.num_joints() != model.skeleton().num_joints()) {
    throw std::invalid_argument("expected a motion on the model's skeleton '" +
                                model.skeleton().name() + "' (" +
                                std::to_string(model.skeleton().num_joints()) + " joints), got " +
                                std::to_string(motion.num_joints()) + " joints");
  }
  if (motion.num_frames() < model.window()) {
    throw std::invalid_argument("the model works on windows of " + std::to_string(model.window()) +
                                " frames; the motion has " + std::to_string(motion.num_frames()));
  }
}

template <typename T>
std::vector<T> Gather(const std::vector<T>& poses, const std::vector<int>& starts, int window,
                      int coords) {
  std::vector<T> w;
  w.reserve(starts.size() * window * coords);
  for (int s : starts) {
    w.insert(w.end(), poses.begin() + static_cast<size_t>(s) * coords,
             poses.begin() + static_cast<size_t>(s + window) * coords);
  }
  return w;
}

}  // namespace

MotionImputation ImputeMotion(const HgvaeModel& model, const Motion& motion,
                              const std::vector<uint8_t>& missing, const ImputeOptions& options,
                              int class_index) {
  CheckMotion(model, motion);
  const int T = motion.num_frames(), J = motion.num_joints(), W = model.window(),
            N = model.coords();
  if (missing.size() != motion.positions().size()) {
    throw std::invalid_argument("the missing-value mask has " + std::to_string(missing.size()) +
                                " values, the motion " + std::to_string(motion.positions().size()));
  }
  MotionImputation out{motion, 0, {}, {}, {}};
  // Root-relative coordinates without the root, and their mask.
  std::vector<float> poses(static_cast<size_t>(T) * N);
  std::vector<uint8_t> mask(poses.size());
  const std::vector<float>& p = motion.positions();
  for (int t = 0; t < T; ++t) {
    const size_t f = static_cast<size_t>(t) * J * 3;
    for (int a = 0; a < 3; ++a) {
      if (missing[f + a]) {
        throw std::invalid_argument(
            "frame " + std::to_string(t) + ": the root joint '" + model.skeleton().joint_name(0) +
            "' has a missing value; it must be known (poses are root-relative)");
      }
    }
    for (int v = 0; v < N; ++v) {
      poses[static_cast<size_t>(t) * N + v] = p[f + 3 + v] - p[f + v % 3];
      mask[static_cast<size_t>(t) * N + v] = missing[f + 3 + v];
      out.missing_values += missing[f + 3 + v];
    }
  }
  if (out.missing_values == 0) return out;
  std::vector<int> starts;
  for (int s : CoveringWindowStarts(T, W, W)) {
    const auto first = mask.begin() + static_cast<size_t>(s) * N,
               last = first + static_cast<size_t>(W) * N;
    if (std::find(first, last, 1) == last) continue;  // nothing missing here
    if (std::all_of(first, last, [](uint8_t m) { return m != 0; })) {
      throw std::invalid_argument("frames " + std::to_string(s) + ".." + std::to_string(s + W - 1) +
                                  ": every value is missing; nothing to impute from");
    }
    starts.push_back(s);
  }
  std::vector<float> start;  // the start's root-relative poses (empty: the mean)
  if (options.start == ImputeStart::kRefiner) {
    start = Gather(
        model.Refine(MakeRefinerFills(model.skeleton(), p, missing, TrainingMeanPose(model))),
        starts, W, N);
  } else if (options.start != ImputeStart::kMean) {
    const std::vector<float> fill =
        InterpolateMissing(p, missing, J,
                           options.start == ImputeStart::kLinear ? Interpolation::kLinear
                                                                 : Interpolation::kCubicSpline,
                           TrainingMeanPose(model));
    start.resize(poses.size());
    for (int t = 0; t < T; ++t) {
      const size_t f = static_cast<size_t>(t) * J * 3;
      for (int v = 0; v < N; ++v)
        start[static_cast<size_t>(t) * N + v] = fill[f + 3 + v] - p[f + v % 3];
    }
    start = Gather(start, starts, W, N);
  }
  const ImputeResult r = model.Impute(Gather(poses, starts, W, N), Gather(mask, starts, W, N),
                                      options, class_index, start.empty() ? nullptr : &start);
  // Average where windows overlap.
  std::vector<double> sum(poses.size(), 0.0);
  std::vector<int> hits(poses.size(), 0);
  for (size_t w = 0; w < starts.size(); ++w) {
    for (size_t i = 0; i < static_cast<size_t>(W) * N; ++i) {
      const size_t g = static_cast<size_t>(starts[w]) * N + i;
      sum[g] += r.windows[w * W * N + i];
      ++hits[g];
    }
  }
  std::vector<float> pos = p;
  for (int t = 0; t < T; ++t) {
    const size_t f = static_cast<size_t>(t) * J * 3;
    for (int v = 0; v < N; ++v) {
      const size_t g = static_cast<size_t>(t) * N + v;
      if (mask[g] && hits[g] > 0)
        pos[f + 3 + v] = static_cast<float>(sum[g] / hits[g]) + p[f + v % 3];
    }
  }
  out.motion = Motion(motion.skeleton_ptr(), motion.fps(), std::move(pos));
  out.window_starts = starts;
  out.score_before = r.score_before;
  out.score_after = r.score_after;
  return out;
}

std::vector<WindowScore> ScoreMotion(const HgvaeModel& model, const Motion& motion, int stride,
                                     int class_index) {
  CheckMotion(model, motion);
  if (stride < 1)
    throw std::invalid_argument("ScoreMotion: expected a stride >= 1, got " +
                                std::to_string(stride));
  const std::vector<float> poses = PoseVectorsWithoutRoot(motion);
  const std::vector<int> starts = CoveringWindowStarts(motion.num_frames(), model.window(), stride);
  const std::vector<double> scores =
      model.Score(Gather(poses, starts, model.window(), model.coords()), class_index);
  std::vector<WindowScore> out;
  for (size_t i = 0; i < starts.size(); ++i)
    out.push_back({starts[i], scores[i], model.OutOfDistribution(scores[i])});
  return out;
}

}  // namespace motionfork
