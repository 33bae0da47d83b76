#include "eval/test_set.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "core/error.h"

namespace motionfork {

std::vector<float> TestSet::LastHistoryPoses() const {
  const int J = num_joints();
  std::vector<float> out(static_cast<size_t>(num_windows()) * pose_dims);
  for (int i = 0; i < num_windows(); ++i) {
    const float* f = history(i) + static_cast<size_t>(t_his - 1) * J * 3;
    float* o = out.data() + static_cast<size_t>(i) * pose_dims;
    for (int j = 1; j < J; ++j) {
      for (int a = 0; a < 3; ++a) o[3 * (j - 1) + a] = f[3 * j + a] - f[a];
    }
  }
  return out;
}

TestSet BuildTestSet(const std::vector<const Clip*>& clips, const ProtocolOptions& protocol) {
  if (protocol.t_his < 1 || protocol.t_pred < 1 || protocol.test_stride < 0 ||
      !(protocol.fps > 0)) {
    throw std::invalid_argument(
        "test windows: expected t_his >= 1, t_pred >= 1, test stride >= 0 "
        "and fps > 0, got " +
        std::to_string(protocol.t_his) + ", " + std::to_string(protocol.t_pred) + ", " +
        std::to_string(protocol.test_stride) + ", " + std::to_string(protocol.fps));
  }
  const int length = protocol.window_length();
  const int stride = protocol.test_stride > 0 ? protocol.test_stride : protocol.t_his;
  TestSet ts;
  ts.t_his = protocol.t_his;
  ts.t_pred = protocol.t_pred;
  std::vector<int> frames;
  for (const Clip* c : clips) {
    if (!ts.skeleton) ts.skeleton = c->motion.skeleton_ptr();
    if (!c->motion.skeleton().SameStructure(*ts.skeleton)) {
      throw std::invalid_argument("test windows: clip '" + c->name + "' is on skeleton '" +
                                  c->motion.skeleton().name() + "', expected '" +
                                  ts.skeleton->name() + "' like the other clips");
    }
    if (std::abs(c->motion.fps() - protocol.fps) > 1e-6 * protocol.fps) {
      throw std::invalid_argument(
          "test windows: clip '" + c->name + "' is at " + std::to_string(c->motion.fps()) +
          " Hz, expected the protocol's " + std::to_string(protocol.fps) + " Hz");
    }
    ts.clip_names.push_back(c->name);
    frames.push_back(c->motion.num_frames());
  }
  ts.windows = SlidingWindows(frames, length, stride, protocol.test_include_last);
  if (ts.windows.empty()) {
    throw std::invalid_argument(
        "no test windows: " + std::to_string(clips.size()) + " clips, none with the " +
        std::to_string(length) + " frames (t_his " + std::to_string(protocol.t_his) + " + t_pred " +
        std::to_string(protocol.t_pred) + ") one window of protocol '" + protocol.name + "' needs");
  }
  const int J = ts.skeleton->num_joints();
  if (J < 2) {
    throw std::invalid_argument("test windows: expected a skeleton of at least 2 joints, got " +
                                std::to_string(J));
  }
  ts.pose_dims = 3 * (J - 1);

  std::map<std::string, int> action_index;
  for (const Clip* c : clips) action_index.emplace(c->action, 0);
  for (auto& [label, index] : action_index) {
    index = static_cast<int>(ts.actions.size());
    ts.actions.push_back(label);
  }

  const size_t n = ts.windows.size();
  ts.histories.resize(n * ts.t_his * J * 3);
  ts.futures.resize(n * ts.t_pred * ts.pose_dims);
  ts.root_futures.resize(n * ts.t_pred * 3);
  ts.action.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Window& w = ts.windows[i];
    const Motion& m = clips[w.clip]->motion;
    ts.action[i] = action_index.at(clips[w.clip]->action);
    std::copy(m.frame(w.start), m.frame(w.start + ts.t_his),
              ts.histories.begin() + i * ts.t_his * J * 3);
    float* out = ts.futures.data() + i * ts.t_pred * ts.pose_dims;
    for (int t = 0; t < ts.t_pred; ++t) {
      const float* f = m.frame(w.start + ts.t_his + t);
      std::copy(f, f + 3, ts.root_futures.begin() + (i * ts.t_pred + t) * 3);
      for (int j = 1; j < J; ++j) {
        for (int a = 0; a < 3; ++a) *out++ = f[3 * j + a] - f[a];
      }
    }
  }
  return ts;
}

bool AttachMultimodalSets(TestSet* test_set, double threshold, const std::string& cache_dir,
                          const std::string& cache_name_prefix) {
  const std::vector<float> last = test_set->LastHistoryPoses();
  std::string path;
  uint64_t key = 0;
  if (!cache_dir.empty()) {
    key = MultimodalCacheKey(last, test_set->pose_dims, threshold);
    char name[64];
    std::snprintf(name, sizeof(name), "-multimodal-%016llx.bin",
                  static_cast<unsigned long long>(key));
    path = (std::filesystem::path(cache_dir) / (cache_name_prefix + name)).string();
    try {
      if (ReadMultimodalCache(path, key, &test_set->multimodal) &&
          test_set->multimodal.num_windows() == test_set->num_windows()) {
        return true;
      }
    } catch (const FormatError&) {
      // A damaged cache is computed again and replaced.
    }
  }
  test_set->multimodal = ComputeMultimodalSets(last, test_set->pose_dims, threshold);
  try {
    if (!path.empty()) WriteMultimodalCache(path, key, test_set->multimodal);
  } catch (const FormatError&) {
    // An unwritable cache folder only costs the next run the computation (the dataset's own cache
    // warns about the folder).
  }
  return false;
}

}  // namespace motionfork
