#include "pipeline/history_repair.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/error.h"
#include "denoise/denoise_metrics.h"
#include "denoise/dvae_model.h"
#include "generator/inference/forecaster.h"
#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"

namespace motionfork::pipeline {

void CheckImputerFits(const HgvaeModel& hg, const std::string& dir, const Forecaster& model) {
  const int t_his = model.config().generator.t_his;
  const double fps = model.config().fps;
  if (hg.skeleton().joint_names() != model.skeleton()->joint_names() || hg.window() != t_his ||
      std::abs(hg.manifest().fps - fps) > 1e-6 * fps) {
    throw FormatError(
        dir + ": the HG-VAE (skeleton '" + hg.skeleton().name() + "', windows of " +
        std::to_string(hg.window()) + " frames at " + std::to_string(hg.manifest().fps) +
        " Hz) does not match the forecaster's history (" + std::to_string(t_his) + " frames at " +
        std::to_string(fps) + " Hz, skeleton '" + model.skeleton()->name() + "')");
  }
}

HistoryImputation ImputeHistory(const HgvaeModel& hg, const std::string& dir,
                                const std::string& file, int start, int t_his,
                                const std::vector<uint8_t>& missing_all, Motion* history) {
  const size_t frame_values = static_cast<size_t>(history->num_joints()) * 3;
  const std::vector<uint8_t> missing(missing_all.begin() + start * frame_values,
                                     missing_all.begin() + (start + t_his) * frame_values);
  MotionImputation r;
  try {
    r = ImputeMotion(hg, history->Slice(start, start + t_his), missing, hg.manifest().impute);
  } catch (const std::invalid_argument& e) {
    throw FormatError(file + ": " + e.what());
  }
  std::vector<float> pos = history->positions();
  std::copy(r.motion.positions().begin(), r.motion.positions().end(),
            pos.begin() + start * frame_values);
  *history = Motion(history->skeleton_ptr(), history->fps(), std::move(pos));
  return HistoryImputation{dir,
                           r.missing_values,
                           r.score_before.at(0),
                           r.score_after.at(0),
                           ToString(hg.manifest().ood_score),
                           hg.manifest().score_mean,
                           hg.manifest().score_std};
}

HistoryDenoising DenoiseHistory(const DvaeModel& dv, const std::string& dir,
                                const std::string& file, int start, int t_his, Motion* history) {
  if (dv.skeleton().joint_names() != history->skeleton().joint_names() ||
      std::abs(dv.manifest().fps - history->fps()) > 1e-6 * history->fps()) {
    throw FormatError(dir + ": the Motion-DVAE (skeleton '" + dv.skeleton().name() + "', " +
                      std::to_string(dv.manifest().fps) +
                      " Hz) does not match the forecaster's (skeleton '" +
                      history->skeleton().name() + "', " + std::to_string(history->fps()) + " Hz)");
  }
  const int end = start + t_his, first = std::max(0, end - std::max(dv.window(), t_his));
  const Motion context = history->Slice(first, end);
  Motion clean;
  try {
    clean = DenoiseMotion(dv, context, dv.manifest().denoise);
  } catch (const std::invalid_argument& e) {
    throw FormatError(file + ": " + e.what());
  }
  const size_t fv = static_cast<size_t>(history->num_joints()) * 3;
  std::vector<float> pos = history->positions();
  const std::vector<float> before(pos.begin() + start * fv, pos.begin() + end * fv);
  std::copy(clean.positions().begin() + (start - first) * fv, clean.positions().end(),
            pos.begin() + start * fv);
  const std::vector<float> after(pos.begin() + start * fv, pos.begin() + end * fv);
  *history = Motion(history->skeleton_ptr(), history->fps(), std::move(pos));
  HistoryDenoising d{dir, ToString(dv.manifest().denoise.mode), end - first,
                     MeanJointError(before, after)};
  d.first_frame = first;
  return d;
}

}  // namespace motionfork::pipeline
