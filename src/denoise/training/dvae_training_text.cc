#include "denoise/training/dvae_training_text.h"

#include "core/text_format.h"
#include "denoise/refiner_blend.h"

namespace motionfork {

std::string DvaeTrainingStartText(DvaeStage stage, const DvaeTrainConfig& config,
                                  const DvaeData& data) {
  std::string s = StringPrintf(
      "Motion-DVAE: windows of %d frames x %d joints; %zu training clips (%s frames), %zu held "
      "out\n",
      stage == DvaeStage::kRefiner ? config.refiner.model.window : config.model.window, data.joints,
      data.train.size(), WithThousands(data.train_frames()).c_str(), data.held_out.size());
  if (stage == DvaeStage::kPrior) return s;
  const bool finetune = stage == DvaeStage::kFinetune;
  s += finetune ? "unsupervised denoising training on noisy windows:"
                : "supervised refiner training on clean windows corrupted at random levels up to:";
  for (const std::string& n : finetune ? config.finetune.noise : config.refiner.noise) s += " " + n;
  return s + (finetune
                  ? " (the encoder, initial-state and noise predictors learn; decoder and "
                    "prior stay fixed)\n"
                  : StringPrintf(" (%.0f%% left clean, acceleration weight %g; only the "
                                 "refiner learns)\n",
                                 100 * config.refiner.clean_share, config.refiner.accel_weight));
}

namespace {

// The refiner's blend weights per bin of correction size, one line ("" without them).
std::string RefinerBlendText(const RefinerBlend& blend) {
  const std::vector<double>& weights = blend.weights;
  if (weights.empty()) return "";
  std::string s = StringPrintf(
      "refiner blend (held-out clips): where the input is rough, the base is the input smoothed "
      "by sigma %.3g frames; weight of the correction by the input's roughness (against its %s "
      "smoothing):",
      blend.sigma, RoughnessName(blend.roughness).c_str());
  const std::string smooth =
      blend.accel_bound > 0
          ? StringPrintf(
                "; where the roughness exceeds %g cm, the output smoothed by the least Gaussian "
                "that brings its acceleration to %.3g x its own smoothed by %g frames",
                kSmoothFromCm, blend.accel_bound, kAccelReferenceSigma)
          : StringPrintf(
                "; where the roughness exceeds %g cm, the output smoothed by sigma %.3g "
                "frames",
                kSmoothFromCm, blend.smooth);
  for (size_t b = 0; b < weights.size(); ++b) {
    StringAppendf(&s, "%s %s %.2f", b ? "," : "", RefinerBlendBinName(static_cast<int>(b)).c_str(),
                  weights[b]);
  }
  return s + (blend.smooth > 0 || blend.accel_bound > 0 ? smooth : "") +
         "; outliers repaired first: " + DescribeOutlierRepair(blend.outliers) + "\n";
}

}  // namespace

std::string DvaeTrainingDoneText(DvaeStage stage, const DvaeTrainSummary& s,
                                 const std::string& out) {
  static const char* const kWhat[] = {
      "motion prior bundle: %s (dvae.yaml, dvae.pt)",
      "denoiser bundle: %s (the epoch with the lowest held-out loss)",
      "bundle with its refiner: %s (denoise mode refiner; the epoch with the lowest held-out "
      "error)"};
  static const char* const kNext[] = {
      "next: motionfork dvae finetune --prior %s --data DIR --out DIR\n",
      "next: motionfork dvae refine --prior %s --data DIR --out DIR\n", ""};
  if (s.blend_only) {
    return StringPrintf(
               "refiner kept as it was, its blend fitted again in %s; bundle: %s "
               "(dvae.yaml; dvae.pt holds the same weights)\n",
               Duration(s.seconds).c_str(), out.c_str()) +
           RefinerBlendText(s.refiner_blend);
  }
  const int k = static_cast<int>(stage);
  const std::string trained =
      s.epochs_done <= s.first_epoch
          ? std::string("every epoch was trained already; ")
          : StringPrintf(
                "trained epochs %d..%d in %s%s; ", s.first_epoch + 1, s.epochs_done,
                Duration(s.seconds).c_str(),
                s.stopped_early ? " (stopped early: the held-out figure stopped improving)" : "");
  return trained + StringPrintf(kWhat[k], out.c_str()) +
         StringPrintf(", log: %s/log.csv\n", out.c_str()) + StringPrintf(kNext[k], out.c_str()) +
         RefinerBlendText(s.refiner_blend);
}

}  // namespace motionfork
