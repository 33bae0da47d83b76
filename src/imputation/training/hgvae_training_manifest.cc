#include "imputation/training/hgvae_training_manifest.h"

#include "bundle/protocol_manifest.h"

namespace motionfork {

HgvaeManifest HgvaeTrainingManifest(const HgvaeTrainConfig& config, const ProtocolOptions& protocol,
                                    const Skeleton& skeleton) {
  HgvaeManifest base = ProtocolManifest<HgvaeManifest>(config, protocol, skeleton);
  base.ood_k = config.ood_k;
  base.ood_score = config.ood_score;
  base.impute = config.impute;
  return base;
}

long long TrainingFrames(const HgvaeData& data) {
  long long frames = 0;
  for (const auto& p : data.train.poses) frames += p.size() / data.coords;
  return frames;
}

}  // namespace motionfork
