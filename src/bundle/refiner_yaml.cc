#include "bundle/refiner_yaml.h"

#include <stdexcept>
#include <vector>

#include "config/yaml_util.h"

namespace motionfork {

using yaml_util::CheckKeys;
using yaml_util::Fail;
using yaml_util::GetOr;

const std::set<std::string>& RefinerModelKeys() {
  static const std::set<std::string> keys = {"channels",  "window",       "stride",
                                             "dilations", "linear_reach", "smooth_start"};
  return keys;
}

const std::set<std::string>& RefinerTrainKeys() {
  static const std::set<std::string> keys = {
      "epochs",    "windows_per_epoch", "batch_size", "learning_rate", "lr_decay",
      "grad_clip", "patience",          "seed",       "threads"};
  return keys;
}

void ParseRefinerModel(const std::string& file, const YAML::Node& n, RefinerOptions* o) {
  o->channels = GetOr<int>(file, n, "channels", o->channels);
  o->window = GetOr<int>(file, n, "window", o->window);
  o->stride = GetOr<int>(file, n, "stride", o->stride);
  o->dilations = GetOr<std::vector<int>>(file, n, "dilations", o->dilations);
  o->linear_reach = GetOr<int>(file, n, "linear_reach", o->linear_reach);
  o->smooth_start = GetOr<bool>(file, n, "smooth_start", o->smooth_start);
  try {
    ValidateRefinerOptions(*o, "refiner");
  } catch (const std::invalid_argument& e) {
    Fail(file, n, e.what());
  }
}

void ParseRefinerTraining(const std::string& file, const YAML::Node& n, RefinerTrainOptions* t) {
  t->epochs = GetOr<int>(file, n, "epochs", t->epochs);
  t->windows_per_epoch = GetOr<int>(file, n, "windows_per_epoch", t->windows_per_epoch);
  t->batch_size = GetOr<int>(file, n, "batch_size", t->batch_size);
  t->learning_rate = GetOr<double>(file, n, "learning_rate", t->learning_rate);
  t->lr_decay = GetOr<double>(file, n, "lr_decay", t->lr_decay);
  t->grad_clip = GetOr<double>(file, n, "grad_clip", t->grad_clip);
  t->patience = GetOr<int>(file, n, "patience", t->patience);
  t->seed = GetOr<uint64_t>(file, n, "seed", t->seed);
  t->threads = GetOr<int>(file, n, "threads", t->threads);
  if (t->epochs < 1 || t->batch_size < 1 || t->windows_per_epoch < t->batch_size ||
      !(t->learning_rate > 0) || !(t->lr_decay > 0 && t->lr_decay <= 1) || t->patience < 1 ||
      t->threads < 1) {
    Fail(file, n,
         "refiner: expected epochs >= 1, batch_size >= 1, windows_per_epoch >= batch_size, "
         "learning_rate > 0, 0 < lr_decay <= 1, patience >= 1, threads >= 1");
  }
}

void ParseManifestRefiner(const std::string& file, const YAML::Node& root, RefinerOptions* o) {
  const YAML::Node r = root["refiner"];
  if (!r) return;
  if (!r.IsMap()) Fail(file, r, "key 'refiner' must be a mapping");
  CheckKeys(file, r, "refiner", RefinerModelKeys());
  ParseRefinerModel(file, r, o);
}

void EmitManifestRefiner(YAML::Emitter& out, const RefinerOptions& o) {
  if (!o.enabled()) return;
  out << YAML::Key << "refiner" << YAML::Value << YAML::BeginMap;
  yaml_util::EmitPairs(out, "channels", o.channels, "window", o.window, "stride", o.stride,
                       "linear_reach", o.linear_reach);
  if (!o.smooth_start) out << YAML::Key << "smooth_start" << YAML::Value << false;
  out << YAML::Key << "dilations" << YAML::Value << YAML::Flow << o.dilations << YAML::EndMap;
}

}  // namespace motionfork
