#include "core/text_format.h"
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

}  // namespace motionfork::pipeline
