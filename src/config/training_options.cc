#include "config/training_options.h"

#include "config/yaml_util.h"

namespace motionfork {

using yaml_util::Fail;
using yaml_util::Get;
using yaml_util::GetOr;

namespace {
template <typename T>
std::vector<T> List(const std::string& path, const YAML::Node& map, const std::string& key,
                    std::vector<T> fallback) {
  const YAML::Node n = map[key];
  if (!n) return fallback;
  if (!n.IsSequence()) Fail(path, n, "'" + key + "' must be a list");
  std::vector<T> out;
  for (const YAML::Node& e : n) out.push_back(e.as<T>());
  return out;
}
}  // namespace

GeneratorTrainConfig LoadGeneratorTrainConfig(const std::string& path) {
  const YAML::Node root = yaml_util::LoadFile(path);
  GeneratorTrainConfig c;
  c.path = path;
  try {
    c.name = Get<std::string>(path, root, "name");
    c.protocol = Get<std::string>(path, root, "protocol");
    c.prior = GetOr<std::string>(path, root, "prior", "");
    c.constraints = GetOr<std::string>(path, root, "constraints", "");
    if (const YAML::Node g = root["generator"]) {
      GeneratorOptions& o = c.generator;
      o.n_pre = GetOr<int>(path, g, "n_pre", o.n_pre);
      o.hidden = GetOr<int>(path, g, "hidden", o.hidden);
      o.blocks = GetOr<int>(path, g, "blocks", o.blocks);
      o.nz = GetOr<int>(path, g, "nz", o.nz);
      o.batch_norm = GetOr<bool>(path, g, "batch_norm", o.batch_norm);
      o.dropout = GetOr<double>(path, g, "dropout", o.dropout);
      o.partition = GetOr<std::string>(path, g, "partition", o.partition);
    }
    if (const YAML::Node l = root["losses"]) {
      LossWeights& w = c.losses;
      w.past_reconstruction = GetOr<double>(path, l, "past_reconstruction", w.past_reconstruction);
      w.limb_length = GetOr<double>(path, l, "limb_length", w.limb_length);
      w.diversity = List<double>(path, l, "diversity", {8, 25});
      w.diversity_scale = List<double>(path, l, "diversity_scale", {100, 300});
      w.best_of_many = GetOr<double>(path, l, "best_of_many", w.best_of_many);
      w.multimodal = GetOr<double>(path, l, "multimodal", w.multimodal);
      w.prior_nll = GetOr<double>(path, l, "prior_nll", w.prior_nll);
      w.angle = GetOr<double>(path, l, "angle", w.angle);
    } else {
      c.losses.diversity = {8, 25};
      c.losses.diversity_scale = {100, 300};
    }
    if (const YAML::Node m = root["multimodal"]) {
      MultimodalOptions& o = c.multimodal;
      o.last_pose_threshold = GetOr<double>(path, m, "last_pose_threshold", o.last_pose_threshold);
      o.future_min_distance = GetOr<double>(path, m, "future_min_distance", o.future_min_distance);
      o.max_per_window = GetOr<int>(path, m, "max_per_window", o.max_per_window);
    }
    TrainingOptions& t = c.training;
    t.samples_per_part = {10, 10};
    if (const YAML::Node n = root["training"]) {
      t.samples_per_part = List<int64_t>(path, n, "samples_per_part", t.samples_per_part);
      t.batch_histories = GetOr<int>(path, n, "batch_histories", t.batch_histories);
      t.epochs = GetOr<int>(path, n, "epochs", t.epochs);
      t.windows_per_epoch = GetOr<int>(path, n, "windows_per_epoch", t.windows_per_epoch);
      t.lr_constant_epochs = GetOr<int>(path, n, "lr_constant_epochs", t.lr_constant_epochs);
      t.learning_rate = GetOr<double>(path, n, "learning_rate", t.learning_rate);
      t.grad_clip = GetOr<double>(path, n, "grad_clip", t.grad_clip);
      t.window_stride = GetOr<int>(path, n, "window_stride", t.window_stride);
      t.prior_frame_step = GetOr<int>(path, n, "prior_frame_step", t.prior_frame_step);
      t.seed = GetOr<uint64_t>(path, n, "seed", t.seed);
      t.threads = GetOr<int>(path, n, "threads", t.threads);
    }
    const size_t parts = t.samples_per_part.size();
    auto rule = [&](bool ok, const std::string& what) {
      if (!ok) throw std::invalid_argument(what);
    };
    rule(parts >= 1, "training.samples_per_part needs one count per body part");
    for (int64_t n : t.samples_per_part)
      rule(n >= 1, "training.samples_per_part entries must be >= 1");
    rule(c.losses.diversity.size() == parts && c.losses.diversity_scale.size() == parts,
         "losses.diversity and losses.diversity_scale need one value per body part (" +
             std::to_string(parts) + ", as training.samples_per_part)");
    rule(t.batch_histories >= 1, "training.batch_histories must be >= 1");
    rule(t.epochs >= 1, "training.epochs must be >= 1");
    rule(t.windows_per_epoch >= t.batch_histories,
         "training.windows_per_epoch must be >= batch_histories");
    rule(t.lr_constant_epochs >= 0 && t.lr_constant_epochs <= t.epochs,
         "training.lr_constant_epochs must be in 0..epochs");
    rule(t.learning_rate > 0, "training.learning_rate must be > 0");
    rule(t.grad_clip > 0, "training.grad_clip must be > 0");
    rule(t.window_stride >= 1, "training.window_stride must be >= 1");
    rule(t.prior_frame_step >= 1, "training.prior_frame_step must be >= 1");
    rule(t.threads >= 1, "training.threads must be >= 1");
    rule(c.multimodal.max_per_window >= 0, "multimodal.max_per_window must be >= 0");
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(path, "", e.what()));
  } catch (const YAML::Exception& e) {
    throw FormatError(FormatMessage(path, "line " + std::to_string(e.mark.line + 1), e.msg));
  }
  return c;
}

}  // namespace motionfork
