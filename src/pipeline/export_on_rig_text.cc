#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "core/text_format.h"
#include "pipeline/export.h"
#include "pipeline/export_on_rig.h"

namespace motionfork::pipeline {

std::string RigSampleText(const WrittenRigSample& w, const UserRig& user, const Prediction& p) {
  const RigSample& s = w.sample;
  std::string text = StringPrintf(
      "wrote %s: sample %d on the rig of %s (%d joints: %d posed from the model, %d held), %d "
      "history + %d future frames at %.6g Hz, %s; largest joint displacement from the "
      "prediction %.2f mm\n",
      w.path.c_str(), s.sample, user.path.c_str(), s.solved_joints + s.held_joints, s.solved_joints,
      s.held_joints, s.history_frames, s.future_frames, s.fps,
      user.roles.empty() ? "values as read" : user.frame.Describe().c_str(), 1000 * s.displacement);
  const bool repaired = p.imputation || p.denoising;
  if (s.history_mismatch > 1e-3 && !repaired) {
    text += StringPrintf(
        "warning: %s: its history lies up to %.1f mm from the prediction's: is it the file the "
        "prediction was made from?\n",
        user.path.c_str(), 1000 * s.history_mismatch);
  }
  return text;
}

std::string ExportSamples(const Prediction& p, const std::string& source, const std::string& out,
                          int sample, const std::string& rig_choice, const BvhWriteOptions& options,
                          const std::string& config_dir) {
  std::string ext = std::filesystem::path(out).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext != ".bvh")
    throw std::invalid_argument("-o '" + out + "': expected a path ending in .bvh");
  ValidateBvhWriteOptions(options);
  const RigChoice rig = RigSource(p, rig_choice, source);
  std::string text = rig.note.empty() ? "" : rig.note + "\n";
  if (!rig.path.empty()) {
    const UserRig user = ReadUserRig(rig.path, p, config_dir);
    for (const WrittenRigSample& w : ExportPredictionOnRig(p, user, out, sample))
      text += RigSampleText(w, user, p);
    return text;
  }
  for (const WrittenSample& w : ExportPrediction(p, source, out, sample, options)) {
    text += StringPrintf(
        "wrote %s: sample %d, %d frames (%d history + %d future) at %.6g Hz, %d joints; "
        "largest joint displacement from the prediction %.3f mm\n",
        w.path.c_str(), w.sample.sample, p.frames(), p.t_his, p.t_pred, p.fps, p.joints(),
        w.sample.deviation * 1000);
  }
  return text;
}

}  // namespace motionfork::pipeline
