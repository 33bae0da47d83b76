// What the HG-VAE and Motion-DVAE training configs (configs/models/hgvae_*.yaml, dvae_*.yaml)
// share: the keys at the top and the keys of the epoch loop that each of their training sections
// has (`training:` of both, `finetune:` of the Motion-DVAE), read the same way into each options
// struct. Each bundle/*_bundle.cc reads its own keys.
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>

#include "config/yaml_util.h"

namespace motionfork {

// `name` (optional) and `protocol`; path = the file the config came from.
template <typename TrainConfig>
void ReadTrainConfigHeader(const std::string& file, const YAML::Node& root, TrainConfig* c) {
  c->path = file;
  c->name = yaml_util::GetOr<std::string>(file, root, "name", "");
  c->protocol = yaml_util::Get<std::string>(file, root, "protocol");
}

// The epoch loop's keys and a section's own, for yaml_util::CheckKeys.
inline std::set<std::string> WithEpochLoopKeys(std::set<std::string> own) {
  own.insert({"epochs", "windows_per_epoch", "batch_size", "learning_rate", "grad_clip", "kl_start",
              "seed", "threads"});
  return own;
}

// The epoch loop's keys present in n into an options struct with these members (HgvaeTrainOptions,
// DvaeTrainOptions, DvaeFinetuneOptions); a missing key keeps the member's default.
template <typename Options>
void ReadEpochLoopKeys(const std::string& file, const YAML::Node& n, Options* o) {
  using yaml_util::GetOr;
  o->epochs = GetOr<int>(file, n, "epochs", o->epochs);
  o->windows_per_epoch = GetOr<int>(file, n, "windows_per_epoch", o->windows_per_epoch);
  o->batch_size = GetOr<int>(file, n, "batch_size", o->batch_size);
  o->learning_rate = GetOr<double>(file, n, "learning_rate", o->learning_rate);
  o->grad_clip = GetOr<double>(file, n, "grad_clip", o->grad_clip);
  o->kl_start = GetOr<double>(file, n, "kl_start", o->kl_start);
  o->seed = GetOr<uint64_t>(file, n, "seed", o->seed);
  o->threads = GetOr<int>(file, n, "threads", o->threads);
}

}  // namespace motionfork
