// What `motionfork train` records in a new bundle's model.yaml before any weight: the protocol's
// timing and skeleton, the network's sizes and the recipe's provenance; and what it reports of
// the training windows.
#pragma once

#include <string>

#include "core/skeleton.h"
#include "dataset/protocol_options.h"
#include "generator/model/generator_options.h"
#include "generator/model/training_options.h"
#include "generator/training/training_data.h"

namespace motionfork {

// skeleton: the protocol's; split_file: as given ("" = the protocol's split).
ModelConfig TrainingModelConfig(const GeneratorTrainConfig& config, const ProtocolOptions& protocol,
                                const Skeleton& skeleton, const std::string& split_file);

// Training windows that have pseudo multimodal futures.
size_t WindowsWithMultimodalFutures(const TrainingWindows& data);

}  // namespace motionfork
