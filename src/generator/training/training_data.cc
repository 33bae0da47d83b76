#include "generator/training/training_data.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "core/heading.h"
#include "io/clip_cache.h"
#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

double TrainingWindows::SpeedThatFits(int w, double speed) const {
  if (speed <= 1) return speed;  // a slower read stays inside the recorded window
  const Window& win = windows.at(w);
  const double last = win.start + t_his - 1;
  const double frames = static_cast<double>(clip_poses[win.clip].size()) / (num_nodes * 3);
  if (t_his > 1) speed = std::min(speed, last / (t_his - 1));
  if (t_pred > 0) speed = std::min(speed, (frames - 1 - last) / t_pred);
  return std::max(1.0, speed);
}

double TrainingWindows::SharedSpeed(int w, int pseudo, double speed) const {
  speed = SpeedThatFits(w, speed);
  const auto& mm = multimodal.at(w);
  for (int m = 0; m < std::min<int>(pseudo, static_cast<int>(mm.size())); ++m)
    speed = SpeedThatFits(mm[m], speed);
  return speed;
}

void TrainingWindows::CopyTurned(int v, double angle, double speed, float* out) const {
  const Window& win = windows.at(v);
  const size_t frame = static_cast<size_t>(num_nodes) * 3;
  const float* clip = clip_poses[win.clip].data();
  if (speed == 1) {
    std::memcpy(out, clip + win.start * frame, num_frames() * frame * sizeof(float));
  } else {
    const double u = SpeedThatFits(v, speed), last = win.start + t_his - 1;
    const size_t clip_frames = clip_poses[win.clip].size() / frame;
    for (int t = 0; t < num_frames(); ++t) {
      const double at = std::clamp(last + u * (t - (t_his - 1)), 0.0, double(clip_frames - 1));
      const size_t f0 = static_cast<size_t>(at), f1 = std::min(f0 + 1, clip_frames - 1);
      const float b = static_cast<float>(at - f0), a = 1.0f - b;
      for (size_t k = 0; k < frame; ++k)
        out[t * frame + k] = a * clip[f0 * frame + k] + b * clip[f1 * frame + k];
    }
  }
  if (up) RotateAboutUp(out, static_cast<size_t>(num_frames()) * num_nodes, angle, *up);
}

void TrainingWindows::Gather(int w, float* out, double speed) const {
  CopyTurned(w, up ? turn[w] : 0.0, speed, out);
}

void TrainingWindows::GatherPseudo(int w, int m, float* out, double speed) const {
  const int v = multimodal.at(w).at(m);
  const double angle = !up ? 0.0 : multimodal_in_body_frame ? turn[v] : turn[w];
  CopyTurned(v, angle, speed, out);
}

namespace {

// Mean over joints of the per-joint distance between poses a and b ([N, 3] each).
float MeanJointDistance(const float* a, const float* b, int nodes) {
  float sum = 0;
  for (int j = 0; j < nodes; ++j) {
    const float dx = a[3 * j] - b[3 * j], dy = a[3 * j + 1] - b[3 * j + 1],
                dz = a[3 * j + 2] - b[3 * j + 2];
    sum += std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  return sum / nodes;
}

// Mean over joints of the per-joint distance between pose a and pose b turned about up by the
// angle whose cosine and sine are c, s (ground axes ga towards gb, as RotateAboutUp).
float MeanJointDistanceTurned(const float* a, const float* b, int nodes, float c, float s, int ga,
                              int gb) {
  float sum = 0;
  for (int j = 0; j < nodes; ++j) {
    float t[3] = {b[3 * j], b[3 * j + 1], b[3 * j + 2]};
    const float x = t[ga], y = t[gb];
    t[ga] = c * x - s * y;
    t[gb] = s * x + c * y;
    const float dx = a[3 * j] - t[0], dy = a[3 * j + 1] - t[1], dz = a[3 * j + 2] - t[2];
    sum += std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  return sum / nodes;
}

// Fills tw's body frame: the up axis, the heading nodes and each window's turn.
void ComputeTurns(const std::string& body_frame, const Skeleton& skeleton, TrainingWindows* tw) {
  if (body_frame.empty()) return;
  tw->up = ParseUp(body_frame);
  const HeadingJoints heading = HeadingNodes(skeleton);
  const size_t frame = static_cast<size_t>(tw->num_nodes) * 3;
  tw->turn.resize(tw->windows.size());
  for (size_t w = 0; w < tw->windows.size(); ++w) {
    const Window& win = tw->windows[w];
    tw->turn[w] = -WindowHeading(tw->clip_poses[win.clip].data() + win.start * frame, tw->t_his,
                                 tw->num_nodes, tw->t_his - 1, heading, *tw->up);
  }
}

std::vector<std::vector<int32_t>> ComputeMultimodal(const TrainingWindows& tw,
                                                    const MultimodalOptions& o,
                                                    const std::function<void(double)>& progress) {
  const int W = static_cast<int>(tw.windows.size()), N = tw.num_nodes, D = N * 3;
  const size_t frame = static_cast<size_t>(D);
  const bool in_body = tw.multimodal_in_body_frame;
  // Last history poses [W, D], in each window's body frame when matched there.
  Eigen::MatrixXf last(W, D);
  std::vector<float> pose(frame);
  for (int w = 0; w < W; ++w) {
    const Window& win = tw.windows[w];
    const float* p = tw.clip_poses[win.clip].data() + (win.start + tw.t_his - 1) * frame;
    std::copy(p, p + frame, pose.begin());
    if (in_body) RotateAboutUp(pose.data(), N, tw.turn[w], *tw.up);
    for (int d = 0; d < D; ++d) last(w, d) = pose[d];
  }
  const auto [ga, gb] = in_body ? GroundAxes(*tw.up) : std::pair<int, int>{0, 2};
  const Eigen::VectorXf sq = last.rowwise().squaredNorm();
  // Mean per-joint distance <= t implies vector L2 <= N * t: a cheap pre-filter by matrix products.
  const float l2_bound = static_cast<float>(N * o.last_pose_threshold);
  std::vector<std::vector<int32_t>> out(W);
  constexpr int kBlock = 512;
  std::vector<std::pair<float, int32_t>> cand;
  for (int b0 = 0; b0 < W; b0 += kBlock) {
    const int rows = std::min(kBlock, W - b0);
    const Eigen::MatrixXf dots = last.middleRows(b0, rows) * last.transpose();  // [rows, W]
    for (int r = 0; r < rows; ++r) {
      const int w = b0 + r;
      const Window& wa = tw.windows[w];
      const float* a_last = tw.clip_poses[wa.clip].data() + (wa.start + tw.t_his - 1) * frame;
      const float* a_fut = a_last + frame;
      cand.clear();
      for (int v = 0; v < W; ++v) {
        if (v == w) continue;
        const float d2 = sq[w] + sq[v] - 2 * dots(r, v);
        if (d2 > l2_bound * l2_bound) continue;
        // Window a's poses against window b's, each in its own frame: b turned by the difference.
        const double turn = in_body ? tw.turn[v] - tw.turn[w] : 0.0;
        const float c = static_cast<float>(std::cos(turn)), sn = static_cast<float>(std::sin(turn));
        auto distance = [&](const float* a, const float* b) {
          return in_body ? MeanJointDistanceTurned(a, b, N, c, sn, ga, gb)
                         : MeanJointDistance(a, b, N);
        };
        const Window& wb = tw.windows[v];
        const float* b_last = tw.clip_poses[wb.clip].data() + (wb.start + tw.t_his - 1) * frame;
        const float dist = distance(a_last, b_last);
        if (dist > o.last_pose_threshold) continue;
        float fut = 0;
        for (int t = 0; t < tw.t_pred; ++t)
          fut += distance(a_fut + t * frame, b_last + (t + 1) * frame);
        if (fut / tw.t_pred < o.future_min_distance) continue;
        cand.emplace_back(dist, v);
      }
      std::sort(cand.begin(), cand.end());
      const size_t keep = std::min(cand.size(), static_cast<size_t>(o.max_per_window));
      for (size_t i = 0; i < keep; ++i) out[w].push_back(cand[i].second);
    }
    if (progress) progress(double(b0 + rows) / W);
  }
  return out;
}

// The pseudo multimodal futures of `windows` windows from a cache file: false when there is none,
// it is for other windows or it is damaged (then it is computed again and replaced).
bool ReadTrainingMultimodalCache(const std::string& cache, size_t windows,
                                 std::vector<std::vector<int32_t>>* multimodal) {
  if (!fs::is_regular_file(cache)) return false;
  try {
    const std::string bytes = ReadFileBytes(cache);
    size_t pos = 0;
    auto get = [&](void* dst, size_t n) {
      if (n > bytes.size() - pos)
        throw FormatError(FormatMessage(cache, "", "truncated cache; delete it"));
      std::memcpy(dst, bytes.data() + pos, n);
      pos += n;
    };
    uint32_t count = 0;
    get(&count, 4);
    if (count != windows) return false;
    multimodal->resize(count);
    for (auto& m : *multimodal) {
      uint32_t n = 0;
      get(&n, 4);
      if (static_cast<uint64_t>(n) * 4 > bytes.size() - pos) return false;  // damaged
      m.resize(n);
      get(m.data(), n * 4);
    }
    return true;
  } catch (const FormatError&) {
    multimodal->clear();
    return false;
  }
}

}  // namespace

TrainingWindows BuildTrainingWindows(const Dataset& dataset, int stride,
                                     const MultimodalOptions& options,
                                     const std::string& body_frame, const std::string& cache_dir,
                                     const std::function<void(double)>& progress) {
  TrainingWindows tw;
  tw.t_his = dataset.protocol.t_his;
  tw.t_pred = dataset.protocol.t_pred;
  tw.num_nodes = dataset.skeleton.skeleton->num_joints() - 1;
  const std::vector<int> train = dataset.ClipIndices(Split::kTrain);
  if (train.empty())
    throw std::invalid_argument("training: the protocol's training split is empty");
  std::ostringstream key;
  key << "mm1|" << dataset.protocol.name << "|" << stride << "|" << options.last_pose_threshold
      << "|" << options.future_min_distance << "|" << options.max_per_window;
  if (options.body_frame) {
    if (body_frame.empty()) {
      throw std::invalid_argument(
          "training: multimodal.body_frame needs a generator in the body's frame");
    }
    key << "|body frame " << body_frame;
  }
  for (int c : train) {
    const Clip& clip = dataset.clips[c];
    tw.clip_poses.push_back(PoseVectorsWithoutRoot(clip.motion));
    key << "|" << clip.name << ":" << clip.motion.num_frames();
  }
  tw.windows =
      SlidingWindows(dataset.ClipFrames(train), tw.num_frames(), stride, /*include_last=*/true);
  if (tw.windows.empty()) {
    throw std::invalid_argument("training: no training clip has the " +
                                std::to_string(tw.num_frames()) + " frames one window needs");
  }
  uint64_t h = Fnv1a64(key.str());
  // Content matters too: hash a sample of the poses.
  for (const auto& p : tw.clip_poses) {
    std::string bytes(reinterpret_cast<const char*>(p.data()),
                      std::min<size_t>(p.size(), 64) * sizeof(float));
    h = Fnv1a64(bytes, h);
  }
  char name[64];
  std::snprintf(name, sizeof(name), "multimodal-%016llx.bin", static_cast<unsigned long long>(h));
  const std::string cache = cache_dir.empty() ? "" : (fs::path(cache_dir) / name).string();
  ComputeTurns(body_frame, *dataset.skeleton.skeleton, &tw);
  tw.multimodal_in_body_frame = options.body_frame;
  if (!cache.empty() && ReadTrainingMultimodalCache(cache, tw.windows.size(), &tw.multimodal)) {
    return tw;
  }
  tw.multimodal = ComputeMultimodal(tw, options, progress);
  if (!cache.empty()) {
    std::string bytes;
    auto put = [&](const void* src, size_t n) { bytes.append(static_cast<const char*>(src), n); };
    const uint32_t count = static_cast<uint32_t>(tw.multimodal.size());
    put(&count, 4);
    for (const auto& m : tw.multimodal) {
      const uint32_t n = static_cast<uint32_t>(m.size());
      put(&n, 4);
      put(m.data(), n * 4);
    }
    try {
      WriteFileAtomically(cache, bytes);
    } catch (const FormatError&) {
      // An unwritable cache folder only costs the next run the computation.
    }
  }
  return tw;
}

}  // namespace motionfork
