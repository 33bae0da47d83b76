#include "pipeline/history_check.h"

#include <algorithm>
#include <cmath>

#include "core/text_format.h"
#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"
#include "rig/body_frame.h"
#include "validity/pose_validator.h"

namespace motionfork::pipeline {
namespace {

std::string Axis(int axis, int sign) { return std::string(sign < 0 ? "-" : "+") + "xyz"[axis]; }

// Size, up axis and left/right as the body shows them, against the model's frame.
void JudgeBodyFrame(const Motion& history, const std::vector<std::string>& roles,
                    const std::string& target_up, std::vector<std::string>* doubts) {
  BodyFrameOptions o;
  o.target_up = target_up;
  const BodyFrame f = DetectBodyFrame(history, {}, roles, o);
  if (!f.unit_detected) {
    doubts->push_back(StringPrintf(
        "scale: the body measures %.3g m (leg + trunk), no human size (a wrong --unit?)",
        f.body_size));
  } else if (std::abs(f.unit - 1.0) > 1e-12) {
    doubts->push_back(StringPrintf(
        "scale: the body measures %.3g m (leg + trunk); it is human-sized only if the values "
        "are %s (a wrong --unit?)",
        f.body_size / f.scale, f.Describe().substr(0, f.Describe().find(',')).c_str()));
  }
  if (!target_up.empty() && f.up_detected &&
      (f.up_axis != f.target_axis || f.up_sign != f.target_sign)) {
    doubts->push_back("axis: the head is above the pelvis along " + Axis(f.up_axis, f.up_sign) +
                      ", the model's up axis is " + Axis(f.target_axis, f.target_sign) +
                      " (a wrong --up?)");
  }
  if (f.left_right_detected && f.swapped) {
    doubts->push_back(StringPrintf(
        "left/right: the knees bend backwards as labelled (%.1f cm behind the hip-ankle lines); "
        "the labels look exchanged (a wrong --left-right?)",
        100 * std::abs(f.knee_forward)));
  }
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// Each bone against the prior's typical length, relative to the body's overall size: a bone
// far longer or shorter than the rest is a joint read from the wrong place.
void JudgeBones(const Motion& history, const std::vector<double>& reference,
                const HistoryCheckOptions& o, std::vector<std::string>* doubts) {
  const Skeleton& s = history.skeleton();
  const int J = s.num_joints(), T = history.num_frames();
  if (reference.size() != static_cast<size_t>(J - 1) || T == 0) return;
  std::vector<double> ratio(J, 0.0);  // [joint] median length / reference, for bones ending there
  std::vector<double> judged;
  for (int j = 1; j < J; ++j) {
    const int p = s.parent(j);
    if (p < 0) continue;
    std::vector<double> lengths;
    for (int t = 0; t < T; ++t) {
      const float* a = history.at(t, j);
      const float* b = history.at(t, p);
      lengths.push_back(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
    }
    ratio[j] = Median(lengths) / reference[j - 1];
    if (reference[j - 1] >= o.min_bone) judged.push_back(ratio[j]);
  }
  const double body = Median(judged);
  if (!(body > 0)) return;
  for (int j = 1; j < J; ++j) {
    if (reference[j - 1] < o.min_bone) continue;
    const double r = ratio[j] / body;
    if (r > o.bone_ratio || r < 1.0 / o.bone_ratio) {
      doubts->push_back(StringPrintf(
          "joint %s: its bone from %s is %.2g times the model's, against %.2g for the body as a "
          "whole (a joint read from the wrong place?)",
          s.joint_name(j).c_str(), s.joint_name(s.parent(j)).c_str(), ratio[j], body));
    }
  }
}

std::string JoinFirst(const std::vector<std::string>& names, size_t most) {
  std::string text;
  for (size_t i = 0; i < names.size() && i < most; ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > most) text += StringPrintf(" and %zu more", names.size() - most);
  return text;
}

}  // namespace

HistoryCheck CheckHistory(const Motion& history, const SampleValidity& scored,
                          const PoseValidator& judge, const HgvaeModel* scorer,
                          const std::vector<std::string>& roles, const std::string& target_up,
                          const HistoryCheckOptions& options) {
  HistoryCheck c;
  const int T = history.num_frames();
  // A skeleton no rig convention names has no roles: its size and axes are not judged.
  if (roles.size() == static_cast<size_t>(history.num_joints()))
    JudgeBodyFrame(history, roles, target_up, &c.doubts);
  JudgeBones(history, judge.reference_bone_lengths(), options, &c.doubts);
  if (T > 0 && scored.violating_frames >= options.violating_share * T) {
    c.doubts.push_back(StringPrintf(
        "angle ranges: %d of %d frames outside (%s)", scored.violating_frames, T,
        JoinFirst(judge.ViolatedConstraints(history.positions().data(), T), 4).c_str()));
  }
  if (!scored.prior_ok) {
    c.doubts.push_back(StringPrintf(
        "prior: %.4g nats per pose, above the bound %.4g (99th percentile of real poses)",
        scored.prior_nll.value_or(NAN), judge.prior_bound().value_or(NAN)));
  }
  if (scorer && T >= scorer->window()) {
    // The window ending at the last history frame (the one the futures continue).
    const int W = scorer->window();
    const std::vector<WindowScore> scores = ScoreMotion(*scorer, history, W);
    c.window_score = scores.back().score;
    c.window_bound = scorer->OodThreshold();
    if (*c.window_score < *c.window_bound) {
      c.doubts.push_back(
          StringPrintf("HG-VAE: window score %.4g, below its bound %.4g (out of distribution)",
                       *c.window_score, *c.window_bound));
    }
  }
  return c;
}

void MarkFuturesOfDoubtedHistory(Prediction* p) {
  if (!p->history_check || p->history_check->doubts.empty()) return;
  for (SampleValidity& v : p->samples) {
    v.history_ok = false;
    v.valid = false;
  }
}

}  // namespace motionfork::pipeline
