#include "denoise/training/dvae_training_manifest.h"

#include "bundle/protocol_manifest.h"

namespace motionfork {

DvaeManifest DvaeTrainingManifest(const DvaeTrainConfig& config, const ProtocolOptions& protocol,
                                  const Skeleton& skeleton) {
  DvaeManifest base = ProtocolManifest<DvaeManifest>(config, protocol, skeleton);
  base.noise_prior = config.noise_prior;
  base.denoise = config.denoise;
  return base;
}

long long TrainingFrames(const DvaeData& data) {
  long long frames = 0;
  for (const auto& c : data.train) frames += c.size() / (3 * data.joints);
  return frames;
}

}  // namespace motionfork
