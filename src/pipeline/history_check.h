// The plausibility gate before forecasting: does a history look like what the model knows? It is
// scored with the model's own checks (its HG-VAE's window score where there is one, the prior NLL
// against its bound, the angle ranges) and its body is measured (size, up axis, left/right, each
// bone against the prior's typical lengths); each finding off the mark is a doubt naming what is
// off ("scale: ...", "axis: ...", "left/right: ...", "joint LowerArm_L: ...", "angle ranges:
// ...", "prior: ...", "HG-VAE: ..."). A doubt is a warning (`predict --strict`: an error); the
// futures of a history with a doubt are not shown as valid.
#pragma once

#include <string>
#include <vector>

#include "core/motion.h"
#include "io/prediction_file.h"

namespace motionfork {
class HgvaeModel;
class PoseValidator;
}  // namespace motionfork

namespace motionfork::pipeline {

// How far a history may stray before it is doubted. Tuned on validation windows cut from the
// Bandai training clips (tests/pipeline/history_check_real_test.cc reports the rates).
struct HistoryCheckOptions {
  // Angle ranges: doubted when at least this share of the history frames violates one.
  double violating_share = 0.5;
  // A bone, relative to the body's median bone ratio to the prior's lengths, outside
  // [1 / bone_ratio, bone_ratio]; bones shorter than min_bone (metres, the prior's) are not judged.
  double bone_ratio = 2.0;
  double min_bone = 0.1;
};

// `history` [t_his frames] on the model's skeleton, in its frame (metres, `target_up`, "" when
// the protocol declares none: the axis is not judged); `scored` is judge.Score of it. `scorer`
// (may be null) is the HG-VAE whose window score is compared with its out-of-distribution bound
// (the windows ending at the last history frame; skipped when the history is shorter than its
// window). `roles` [J] are the model's joints' roles (rig/joint_mapping.h, RolesOfSkeleton);
// empty (a skeleton no convention names): size, up axis and left/right are not judged.
HistoryCheck CheckHistory(const Motion& history, const SampleValidity& scored,
                          const PoseValidator& judge, const HgvaeModel* scorer,
                          const std::vector<std::string>& roles, const std::string& target_up,
                          const HistoryCheckOptions& options = {});

// The start of a doubt raised while the file was read onto the model (a "warning: " note of
// ConformForModel: turned over, sides exchanged), already reported with the file's notes.
inline const std::string kReadingDoubt = "reading: ";

// Marks every future of `p` as failing the "history" judge when p.history_check has a doubt.
void MarkFuturesOfDoubtedHistory(Prediction* p);

}  // namespace motionfork::pipeline
