// `motionfork denoise` as library code: a complete motion on the model's skeleton, optionally
// corrupted first (--add-noise, a test), denoised by a Motion-DVAE; and its report for people.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/motion.h"
#include "denoise/dvae_model.h"

namespace motionfork::pipeline {

struct DenoisedFile {
  Motion input;  // as read (the clean reference when noise was added)
  Motion noisy;  // what was denoised: input, or input with `noise` added
  Motion denoised;
  DenoiseOptions options;
  DenoiseStats stats;
  std::string noise;  // the noise spec added ("" = none), e.g. gaussian:0.05
  uint64_t noise_seed = 0;
};

// Throws FormatError naming `path` for a bad noise spec, fewer than 2 frames or a motion the
// model cannot take.
DenoisedFile DenoiseFile(const DvaeModel& model, const std::string& path, const Motion& input,
                         const std::string& noise, uint64_t noise_seed,
                         const DenoiseOptions& options,
                         const std::function<void(double)>& progress = {});

// What the command prints once `out` is written: the noise added, the denoising report, the
// errors against the file before the noise, the noise model, and the file written.
std::string DenoisedFileText(const DvaeModel& model, const DenoisedFile& d, const std::string& out);

}  // namespace motionfork::pipeline
