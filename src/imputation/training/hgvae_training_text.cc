#include "imputation/training/hgvae_training_text.h"

#include "core/text_format.h"

namespace motionfork {

std::string HgvaeDataText(const HgvaeData& data, int window) {
  return StringPrintf(
      "HG-VAE: windows of %d frames x %d coordinates; %zu training clips (%s frames), %zu held "
      "out%s\n",
      window, data.coords, data.train.poses.size(), WithThousands(data.train_frames()).c_str(),
      data.held_out.poses.size(),
      data.classes.empty()
          ? ""
          : (", " + std::to_string(data.classes.size()) + " action classes").c_str());
}

std::string HgvaeTrainingDoneText(const HgvaeTrainSummary& s, const HgvaeTrainConfig& config,
                                  const std::string& out) {
  const int epochs = config.training.epochs;
  if (s.first_epoch >= epochs) {
    return StringPrintf(
        "all %d epochs were trained already; imputation defaults, OoD score and its statistics "
        "(%s) refreshed from the config; bundle: %s\n",
        epochs, ToString(config.ood_score), out.c_str());
  }
  return StringPrintf(
      "trained epochs %d..%d in %s; bundle: %s (hgvae.yaml, hgvae.pt), log: %s/log.csv\n",
      s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(), out.c_str(), out.c_str());
}

std::string HgvaeRefineDoneText(const HgvaeTrainSummary& s, const std::string& out) {
  return StringPrintf(
      "refiner trained epochs %d..%d in %s; bundle with its refiner: %s (impute start refiner; "
      "the epoch with the lowest held-out loss), log: %s/log.csv\n",
      s.first_epoch + 1, s.epochs_done, Duration(s.seconds).c_str(), out.c_str(), out.c_str());
}

}  // namespace motionfork
