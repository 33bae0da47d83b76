// Training windows for the generator and their pseudo multimodal futures (no LibTorch).
//
// Windows: every `stride`-th start in every training clip, t_his + t_pred frames, poses
// root-relative without the root. Pseudo multimodal futures (GSPS): other windows whose last
// history pose is within a mean per-joint distance of this one's and whose future differs by at
// least a given mean per-joint distance; the closest ones first, up to a maximum. Built once and
// cached (the cache key covers the clips and the options). For a generator in the body's frame
// the poses are compared as that generator sees them: each window turned into the body's frame
// of its last history frame (core/heading.h), so that a pose's pseudo futures do not depend on
// which way it faced (training then retargets them in that frame too).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/heading.h"
#include "dataset/dataset.h"
#include "dataset/windows.h"
#include "generator/model/training_options.h"

namespace motionfork {

struct TrainingWindows {
  int t_his = 0, t_pred = 0, num_nodes = 0;
  std::vector<std::vector<float>> clip_poses;    // per clip [T_c, N, 3], root-relative, no root
  std::vector<Window> windows;                   // (clip, start)
  std::vector<std::vector<int32_t>> multimodal;  // per window: indices of pseudo futures
  // In the body's frame (else empty): the up axis, the heading nodes and per window the turn
  // (radians) that brings it into the body's frame of its last history frame (TurnToBodyFrame's).
  std::optional<UpAxis> up;
  HeadingJoints heading;
  std::vector<double> turn;

  int num_frames() const { return t_his + t_pred; }
  // Copies window w's frames into out [T, N, 3], turned by turn[w] when in the body's frame.
  void Gather(int w, float* out) const;
};

// body_frame: GeneratorOptions::body_frame ("" = the data's own axes; else the up axis, the
// heading from the skeleton's FindHeadingJoints). progress(fraction) is called while the
// multimodal sets are computed. cache_dir "" = no cache.
TrainingWindows BuildTrainingWindows(const Dataset& dataset, int stride,
                                     const MultimodalOptions& options,
                                     const std::string& body_frame, const std::string& cache_dir,
                                     const std::function<void(double)>& progress = nullptr);

}  // namespace motionfork
