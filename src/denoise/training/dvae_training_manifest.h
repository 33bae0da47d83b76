// What `motionfork dvae train` hands TrainDvae as the new bundle's manifest (dvae_training.h: the
// protocol's timing and skeleton, the noise prior, the denoising defaults and the recipe's
// provenance), and what it reports of the training data.
#pragma once

#include "core/skeleton.h"
#include "dataset/protocol_options.h"
#include "denoise/dvae_options.h"
#include "denoise/training/dvae_training.h"

namespace motionfork {

// skeleton: the protocol's.
DvaeManifest DvaeTrainingManifest(const DvaeTrainConfig& config, const ProtocolOptions& protocol,
                                  const Skeleton& skeleton);

// Frames of the training clips (held-out ones not counted).
long long TrainingFrames(const DvaeData& data);

}  // namespace motionfork
