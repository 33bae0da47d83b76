// The real Bandai clips (../shared/data/bandai) as the tests on real data read them: the bandai
// protocol and skeleton from configs/, the dataset loaded with its cache in a folder of the
// caller's. Header-only; a test that includes it links motionfork_dataset and motionfork_config.
#pragma once

#include <string>

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"

namespace motionfork::testing {

struct RealBandai {
  ProtocolOptions protocol;
  Dataset dataset;
};

// data: the folder (SharedDataDir("data/bandai")); cache_dir: where the dataset cache goes.
inline RealBandai LoadRealBandai(const std::string& data, const std::string& cache_dir) {
  RealBandai out;
  out.protocol =
      LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", "bandai"));
  const SkeletonConfig skeleton = LoadSkeletonConfig(
      ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", out.protocol.skeleton));
  DatasetLoadOptions load;
  load.cache_dir = cache_dir;
  out.dataset = LoadDataset(out.protocol, skeleton, data, load);
  return out;
}

}  // namespace motionfork::testing
