// Repairing a history before forecasting: its missing values filled by an HG-VAE, its noise
// removed by a Motion-DVAE. Both work on the history frames [start, start + t_his) of a motion on
// the forecaster's skeleton and frame rate; observed values outside those frames are untouched.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/motion.h"
#include "io/prediction_file.h"

namespace motionfork {
class DvaeModel;
class Forecaster;
class HgvaeModel;
}  // namespace motionfork

namespace motionfork::pipeline {

// Throws FormatError naming `imputer_dir` when the HG-VAE's skeleton, window (frames) or frame
// rate differ from the forecaster's history.
void CheckImputerFits(const HgvaeModel& imputer, const std::string& imputer_dir,
                      const Forecaster& forecaster);

// Fills the missing values of history frames [start, start + t_his) of *history (`missing`:
// [T, J, 3] over the whole motion, 1 = missing) with the HG-VAE; observed values are kept
// exactly. `file` names the motion in errors, `imputer_dir` the HG-VAE in the result.
HistoryImputation ImputeHistory(const HgvaeModel& imputer, const std::string& imputer_dir,
                                const std::string& file, int start, int t_his,
                                const std::vector<uint8_t>& missing, Motion* history);

// Denoises the history frames [start, start + t_his) of *history with the Motion-DVAE, together
// with up to one model window of frames before them (never a frame after them). Throws
// FormatError naming `denoiser_dir` when its skeleton or frame rate differ from the history's.
HistoryDenoising DenoiseHistory(const DvaeModel& denoiser, const std::string& denoiser_dir,
                                const std::string& file, int start, int t_his, Motion* history);

}  // namespace motionfork::pipeline
