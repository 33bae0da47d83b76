#include "pipeline/prior_score_text.h"

#include <cmath>

#include "core/text_format.h"

namespace motionfork::pipeline {

std::string PriorScoreText(const std::string& file, const std::string& model,
                           const PosePrior& prior, const Motion& motion, const PriorScore& s,
                           bool per_frame) {
  const int T = static_cast<int>(s.nll.size());
  const bool known = std::isfinite(s.held_out_q99);
  std::string text;
  StringAppendf(&text, "file:      %s (%d frames at %.6g Hz)\n", file.c_str(), T, motion.fps());
  StringAppendf(
      &text, "prior:     %s (skeleton %s, trained on %s)\n", model.c_str(),
      prior.skeleton().name().c_str(),
      prior.summary().protocol.empty() ? "unknown data" : prior.summary().protocol.c_str());
  if (per_frame) {
    StringAppendf(&text, "\n%6s %12s\n", "frame", "NLL");
    for (int t = 0; t < T; ++t) {
      StringAppendf(
          &text, "%6d %12.4f%s\n", t, s.nll[t],
          known && s.nll[t] > s.held_out_q99 ? "  above the 99th percentile of real poses" : "");
    }
    text += "\n";
  }
  StringAppendf(&text,
                "NLL (nats per pose; lower = more plausible): mean %.4f, median %.4f, best %.4f "
                "(frame %d), worst %.4f (frame %d)\n",
                s.mean, s.median, s.min, s.best_frame, s.max, s.worst_frame);
  if (known) {
    StringAppendf(&text,
                  "real held-out poses score: median %.4f, 99th percentile %.4f; frames above it: "
                  "%d of %d (%.1f%%)\n",
                  s.held_out_q50, s.held_out_q99, s.above_q99, T, 100.0 * s.above_q99 / T);
  }
  return text;
}

std::string PriorSampleText(const PosePrior& prior, int count, const std::string& out) {
  return StringPrintf(
      "wrote %s poses (skeleton %s, %d joints, metres, root at the origin, mean training bone "
      "lengths) to %s\n",
      WithThousands(count).c_str(), prior.skeleton().name().c_str(), prior.skeleton().num_joints(),
      out.c_str());
}

}  // namespace motionfork::pipeline
