// What `motionfork hgvae train` hands TrainHgvae as the new bundle's manifest (hgvae_training.h:
// the protocol's timing and skeleton, the out-of-distribution rule, the imputation defaults and
// the recipe's provenance), and what it reports of the training data.
#pragma once

#include "core/skeleton.h"
#include "dataset/protocol_options.h"
#include "imputation/hgvae_options.h"
#include "imputation/training/hgvae_training.h"

namespace motionfork {

// skeleton: the protocol's.
HgvaeManifest HgvaeTrainingManifest(const HgvaeTrainConfig& config, const ProtocolOptions& protocol,
                                    const Skeleton& skeleton);

// Frames of the training clips (held-out ones not counted).
long long TrainingFrames(const HgvaeData& data);

}  // namespace motionfork
