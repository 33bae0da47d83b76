// Training windows for the generator and their pseudo multimodal futures (no LibTorch).
//
// Windows: every `stride`-th start in every training clip, t_his + t_pred frames, poses
// root-relative without the root. Pseudo multimodal futures (GSPS): other windows whose last
// history pose is within a mean per-joint distance of this one's and whose future differs by at
// least a given mean per-joint distance; the closest ones first, up to a maximum. Built once and
// cached (the cache key covers the clips and the options). For a generator in the body's frame
// every window is turned into the body's frame of its last history frame (core/heading.h); its
// pseudo futures are matched either in the data's axes, as GSPS (each then turned with the
// window it serves), or with MultimodalOptions::body_frame each window in its own body frame, so
// that a pose's pseudo futures do not depend on which way it faced.
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
  // In the body's frame (else empty): the up axis and per window the turn (radians) that brings
  // it into the body's frame of its last history frame (TurnToBodyFrame's).
  std::optional<UpAxis> up;
  std::vector<double> turn;
  bool multimodal_in_body_frame = false;  // how `multimodal` was matched (MultimodalOptions)

  int num_frames() const { return t_his + t_pred; }
  // Copies window w's frames into out [T, N, 3], turned by turn[w] when in the body's frame.
  // speed != 1 (training augmentation): the frames read `speed` times faster about the window's
  // last history frame (frame t of the window is clip frame last + speed * (t - (t_his - 1)),
  // interpolated linearly), the factor lowered to the largest the clip holds where it ends
  // first. speed 1 copies the recorded frames as they are.
  void Gather(int w, float* out, double speed = 1) const;
  // Copies window multimodal[w][m] (a pseudo multimodal window of w) into out [T, N, 3] as it
  // was matched beside window w: in the body's frame turned by its own turn when matched there,
  // else by turn[w] (the two windows keep the headings they had to each other in the data's
  // axes); as recorded when there is no body frame. `speed` as Gather's, about its own last
  // history frame.
  void GatherPseudo(int w, int m, float* out, double speed = 1) const;
  // The speed Gather reads window w at when asked for `speed` (lowered where the clip ends).
  double SpeedThatFits(int w, double speed) const;
  // The speed that fits window w and its first `pseudo` pseudo multimodal windows alike, so that
  // a window and the futures it is matched with are read at one speed.
  double SharedSpeed(int w, int pseudo, double speed) const;

 private:
  // Copies window v's frames into out [T, N, 3] at `speed`, turned by `angle` when in the body's
  // frame.
  void CopyTurned(int v, double angle, double speed, float* out) const;
};

// body_frame: GeneratorOptions::body_frame ("" = the data's own axes; else the up axis, the
// heading from the skeleton's FindHeadingJoints). options.body_frame needs it. progress(fraction)
// is called while the multimodal sets are computed. cache_dir "" = no cache.
TrainingWindows BuildTrainingWindows(const Dataset& dataset, int stride,
                                     const MultimodalOptions& options,
                                     const std::string& body_frame, const std::string& cache_dir,
                                     const std::function<void(double)>& progress = nullptr);

}  // namespace motionfork
