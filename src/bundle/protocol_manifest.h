// What every bundle of a model trained on a protocol records of it and of its training recipe:
// the protocol's name and frame rate, its skeleton, and the config's name, seed and epochs.
#pragma once

#include <string>

#include "core/skeleton.h"
#include "dataset/protocol_options.h"

namespace motionfork {

// Manifest: a bundle manifest with protocol, fps, skeleton (a SkeletonSpec) and info (pairs of
// strings); Config: a training config with name, training.seed and training.epochs. skeleton: the
// protocol's.
template <typename Manifest, typename Config>
Manifest ProtocolManifest(const Config& config, const ProtocolOptions& protocol,
                          const Skeleton& skeleton) {
  Manifest m;
  m.protocol = protocol.name;
  m.fps = protocol.fps;
  m.skeleton = skeleton.ToSpec();
  m.info = {{"config", config.name},
            {"seed", std::to_string(config.training.seed)},
            {"epochs", std::to_string(config.training.epochs)}};
  return m;
}

}  // namespace motionfork
