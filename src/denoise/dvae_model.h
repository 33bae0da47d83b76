// A trained Motion-DVAE, ready to use (no LibTorch in this header): denoising of whole sequences
// in regression mode (one pass of the fine-tuned encoder) or optimisation mode (the encoder,
// initial-state and noise predictors take Adam steps on the sequence's own loss first; the
// bundle is left unchanged), reconstruction and sampling with the prior.
//
// Sequences are [frames, joints, 3] floats on the bundle's skeleton and frame rate, metres.
// Long sequences are cut into windows of window() frames every `stride` frames and blended.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/motion.h"
#include "core/skeleton.h"
#include "denoise/dvae_options.h"

namespace motionfork {

class DvaeNet;  // denoise/dvae_net.h (LibTorch)

struct DenoiseStats {
  int windows = 0;
  double seconds = 0;  // wall time of the denoising (not loading)
  std::vector<double>
      noise_std;  // per joint: the noise model's typical std (sqrt(beta / alpha)), metres
};

class DvaeModel {
 public:
  // A model over a built network (in eval mode) and the manifest it was built from. Bundles on
  // disk: bundle/dvae_bundle.h (LoadDvaeModel).
  static DvaeModel FromNet(DvaeManifest manifest, DvaeNet net);

  const DvaeManifest& manifest() const;
  const Skeleton& skeleton() const;
  int window() const;
  int joints() const;
  int64_t num_parameters() const;
  // Threads sharing the windows of one Denoise call (>= 1; default 1), with the same result for
  // any number: windows go in fixed chunks, each with its own seed. A setting of this copy of the
  // model only. Pin LibTorch's own pool to one thread (PinThreads(1)) when using several.
  void set_threads(int threads);
  int threads() const { return threads_; }

  // Denoised copies of the sequences (each >= 2 frames). Deterministic for options.seed.
  // Throws std::invalid_argument for a sequence whose size is not a multiple of joints x 3 or
  // that holds a non-finite value (naming the sequence and frame).
  // progress (optional) gets the share of windows done, 0..1.
  std::vector<std::vector<float>> Denoise(const std::vector<std::vector<float>>& sequences,
                                          const DenoiseOptions& options,
                                          DenoiseStats* stats = nullptr,
                                          const std::function<void(double)>& progress = {}) const;

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
  int threads_ = 1;
};

// A motion on the model's skeleton (same joint names, in order) and frame rate, denoised. Throws
// std::invalid_argument naming what does not match.
Motion DenoiseMotion(const DvaeModel& model, const Motion& motion, const DenoiseOptions& options,
                     DenoiseStats* stats = nullptr,
                     const std::function<void(double)>& progress = {});

}  // namespace motionfork
