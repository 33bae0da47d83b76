// Test windows of a protocol, ready for evaluation: each window's history (the predictor's input)
// and future (the ground truth, as pose vectors), its action label, and the multimodal
// ground-truth sets (eval/multimodal.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/skeleton.h"
#include "dataset/dataset.h"
#include "dataset/protocol_options.h"
#include "dataset/windows.h"
#include "eval/multimodal.h"

namespace motionfork {

struct TestSet {
  std::shared_ptr<const Skeleton> skeleton;  // the protocol skeleton, J joints, root first
  int t_his = 0;                             // frames
  int t_pred = 0;                            // frames
  int pose_dims = 0;                         // D = 3 (J - 1): root-relative, root dropped
  std::vector<std::string> clip_names;       // of the clips the windows come from
  std::vector<Window> windows;               // [N]; Window::clip indexes clip_names
  std::vector<std::string> actions;          // distinct action labels, sorted ("" if unlabelled)
  std::vector<int> action;                   // [N] index into actions
  std::vector<float> histories;              // [N, t_his, J, 3] metres, world coordinates
  std::vector<float> futures;                // [N, t_pred, D] metres, pose vectors
  std::vector<float> root_futures;           // [N, t_pred, 3] metres, the root, world coordinates
  MultimodalSets multimodal;                 // empty until AttachMultimodalSets

  int num_windows() const { return static_cast<int>(windows.size()); }
  int num_joints() const { return skeleton->num_joints(); }
  const float* history(int i) const {
    return histories.data() + static_cast<size_t>(i) * t_his * num_joints() * 3;
  }
  const float* future(int i) const {
    return futures.data() + static_cast<size_t>(i) * t_pred * pose_dims;
  }
  const float* root_future(int i) const {
    return root_futures.data() + static_cast<size_t>(i) * t_pred * 3;
  }
  // Last history pose as a pose vector: [D] metres (the key of the multimodal sets).
  std::vector<float> LastHistoryPoses() const;  // [N, D]
};

// Windows slide over every clip with the protocol's test stride and include-last rule
// (SlidingWindows); each is t_his + t_pred frames. Clips must be on one skeleton (the protocol's)
// and at the protocol frame rate. Throws std::invalid_argument when the clips give no window
// (naming how many clips there were and the window length), or when the clips' skeletons differ.
TestSet BuildTestSet(const std::vector<const Clip*>& clips, const ProtocolOptions& protocol);

// Computes the multimodal sets of the test set with the protocol's threshold, or reads them from
// cache_dir ("" = no cache). The cache key covers the threshold and every last history pose, so a
// stale file is never used. Returns true when they came from the cache.
bool AttachMultimodalSets(TestSet* test_set, double threshold, const std::string& cache_dir,
                          const std::string& cache_name_prefix);

}  // namespace motionfork
