#include "pipeline/denoise_file.h"

#include <stdexcept>

#include "core/error.h"
#include "core/motion_noise.h"
#include "core/text_format.h"
#include "denoise/denoise_metrics.h"
#include "denoise/denoised_motion_text.h"

namespace motionfork::pipeline {

DenoisedFile DenoiseFile(const DvaeModel& model, const std::string& path, const Motion& input,
                         const std::string& noise, uint64_t noise_seed,
                         const DenoiseOptions& options,
                         const std::function<void(double)>& progress) {
  DenoisedFile d{input, input, {}, options, {}, noise, noise_seed};
  if (!noise.empty()) {
    NoiseSpec spec;
    try {
      spec = ParseNoiseSpec(noise);
    } catch (const std::invalid_argument& e) {
      throw FormatError(std::string("--add-noise: ") + e.what());
    }
    d.noisy = AddNoise(input, spec, noise_seed);
  }
  if (d.noisy.num_frames() < 2) {
    throw FormatError(path + ": expected at least 2 frames, found " +
                      std::to_string(d.noisy.num_frames()));
  }
  try {
    d.denoised = DenoiseMotion(model, d.noisy, options, &d.stats, progress);
  } catch (const std::invalid_argument& e) {
    throw FormatError(path + ": " + e.what());
  }
  return d;
}

std::string DenoisedFileText(const DvaeModel& model, const DenoisedFile& d,
                             const std::string& out) {
  std::string text;
  if (!d.noise.empty()) {
    text += StringPrintf("added %s noise (seed %llu) before denoising\n", d.noise.c_str(),
                         static_cast<unsigned long long>(d.noise_seed));
  }
  text += DenoisedMotionText(model, d.options, d.stats, d.noisy, d.denoised);
  if (!d.noise.empty()) {
    text += StringPrintf(
        "against the file before --add-noise: noisy %.2f cm, denoised %.2f cm per joint\n",
        100 * MeanJointError(d.noisy.positions(), d.input.positions()),
        100 * MeanJointError(d.denoised.positions(), d.input.positions()));
  }
  text += NoiseModelText(model, d.stats);
  text += StringPrintf("wrote %s (%d frames, %.6g Hz)\n", out.c_str(), d.denoised.num_frames(),
                       d.denoised.fps());
  return text;
}

}  // namespace motionfork::pipeline
