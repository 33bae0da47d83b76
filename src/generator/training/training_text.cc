#include "generator/training/training_text.h"

#include "core/text_format.h"
#include "generator/training/training_manifest.h"

namespace motionfork {

namespace {

// Loss term names as the progress bar shows them.
std::string ShortTermName(const std::string& name) {
  static const std::pair<const char*, const char*> kShort[] = {
      {"total", "loss"},       {"past_reconstruction", "past"},
      {"limb_length", "limb"}, {"diversity_", "div"},
      {"best_of_many", "bom"}, {"multimodal", "mm"},
      {"prior_nll", "prior"},  {"angle", "angle"}};
  for (const auto& [full, brief] : kShort) {
    if (name.rfind(full, 0) == 0) return brief + name.substr(std::string(full).size());
  }
  return name;
}

}  // namespace

std::string TrainingTermsText(const std::vector<std::pair<std::string, double>>& terms) {
  std::string text;
  for (const auto& [name, v] : terms)
    StringAppendf(&text, "%s%s %.3g", text.empty() ? "" : " ", ShortTermName(name).c_str(), v);
  return text;
}

std::string TrainingDoneText(const TrainSummary& s, int epochs, const std::string& out) {
  if (s.first_epoch >= epochs) {
    return StringPrintf(
        "all %d epochs were trained already; bundle: %s (constraints.yaml and prior/ copied "
        "again), log: %s/log.csv\n",
        epochs, out.c_str(), out.c_str());
  }
  std::string text = StringPrintf(
      "trained epochs %d..%d in %s; bundle: %s (model.yaml, generator.pt), log: %s/log.csv\n",
      s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(), out.c_str(), out.c_str());
  if (s.workers > 1) {
    StringAppendf(&text,
                  "gradient all-reduce: %.2f s of %.2f s (%.1f%%), %lld steps, %.3f MB of "
                  "gradients a step, %d workers\n",
                  s.reduce_seconds, s.seconds, 100 * s.reduce_seconds / s.seconds,
                  static_cast<long long>(s.steps), s.gradient_mb, s.workers);
    if (s.sync_calls > 0) {
      StringAppendf(&text, "batch-norm sums: %.2f s of %.2f s (%.1f%%), %lld calls\n",
                    s.sync_seconds, s.seconds, 100 * s.sync_seconds / s.seconds,
                    static_cast<long long>(s.sync_calls));
    }
  }
  return text;
}

std::string TrainingSetupText(const TrainingWindows& data, int stride,
                              const LossHookSources& losses) {
  std::string s =
      StringPrintf("training windows: %zu (stride %d), %zu with pseudo multimodal futures\n",
                   data.windows.size(), stride, WindowsWithMultimodalFutures(data));
  if (!losses.constraints_path.empty()) {
    StringAppendf(&s, "angle loss: %d constraints from %s\n", losses.constraints,
                  losses.constraints_path.c_str());
  }
  if (!losses.prior_dir.empty()) StringAppendf(&s, "prior loss: %s\n", losses.prior_dir.c_str());
  return s;
}

}  // namespace motionfork
