#include "denoise/denoised_motion_text.h"

#include <algorithm>

#include "core/text_format.h"
#include "denoise/denoise_metrics.h"

namespace motionfork {

std::string DenoisedMotionText(const DvaeModel& model, const DenoiseOptions& options,
                               const DenoiseStats& stats, const Motion& input,
                               const Motion& output) {
  const std::string iterations = options.mode == DenoiseMode::kOptimisation
                                     ? ", " + std::to_string(options.iterations) + " iterations"
                                     : "";
  return StringPrintf(
      "denoised %d frames (%d window%s of <= %d frames, %s mode%s) in %.3f s (%.0f frames/s); "
      "mean change %.2f cm per joint\n",
      output.num_frames(), stats.windows, stats.windows == 1 ? "" : "s",
      options.mode == DenoiseMode::kRefiner ? model.manifest().refiner.window : model.window(),
      ToString(options.mode), iterations.c_str(), stats.seconds,
      output.num_frames() / std::max(1e-9, stats.seconds),
      100 * MeanJointError(input.positions(), output.positions()));
}

std::string NoiseModelText(const DvaeModel& model, const DenoiseStats& stats) {
  if (stats.noise_std.empty()) return "";  // refiner mode: no noise model
  std::string s = "noise model's typical std per joint (cm):";
  for (int j = 0; j < model.joints(); ++j) {
    StringAppendf(&s, " %s %.1f", model.skeleton().joint_names()[j].c_str(),
                  100 * stats.noise_std[j]);
  }
  return s + "\n";
}

}  // namespace motionfork
